// pregrasp plan viewer, part 2 of 4: a small WebGL renderer of its own (no library), drawing
// the triangle lists of math.js.

// ---------- the WebGL renderer ----------

const VERTEX_SHADER = `
attribute vec3 aPos;
attribute vec3 aNormal;
uniform mat4 uModel;
uniform mat4 uViewProj;
uniform mat3 uNormal;
varying vec3 vWorld;
varying vec3 vNormal;
void main() {
  vec4 w = uModel * vec4(aPos, 1.0);
  vWorld = w.xyz;
  vNormal = uNormal * aNormal;
  gl_Position = uViewProj * w;
}`;

// Lambert with a sky/ground ambient; normals face the eye (two-sided, any winding).
const FRAGMENT_SHADER = `
precision mediump float;
uniform vec4 uColor;
uniform float uLit;
uniform vec3 uEye;
uniform vec3 uLight;
varying vec3 vWorld;
varying vec3 vNormal;
void main() {
  vec3 n = normalize(vNormal);
  if (dot(n, uEye - vWorld) < 0.0) n = -n;
  float sky = 0.5 + 0.5 * n.z;
  vec3 lit = uColor.rgb * (0.38 + 0.22 * sky + 0.5 * max(dot(n, uLight), 0.0));
  gl_FragColor = vec4(mix(uColor.rgb, lit, uLit), uColor.a);
}`;

class Renderer {
  /** Throws when WebGL is not available. */
  constructor(container) {
    this.canvas = document.createElement('canvas');
    container.appendChild(this.canvas);
    const options = { antialias: true, preserveDrawingBuffer: true };
    const gl = this.canvas.getContext('webgl', options) || this.canvas.getContext('experimental-webgl', options);
    if (!gl) {
      this.canvas.remove();
      throw new Error('this browser gives the page no WebGL context');
    }
    this.gl = gl;
    const compile = (type, text) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, text);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error('shader: ' + gl.getShaderInfoLog(s));
      return s;
    };
    const prog = gl.createProgram();
    gl.attachShader(prog, compile(gl.VERTEX_SHADER, VERTEX_SHADER));
    gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error('program: ' + gl.getProgramInfoLog(prog));
    gl.useProgram(prog);
    this.attr = { pos: gl.getAttribLocation(prog, 'aPos'), normal: gl.getAttribLocation(prog, 'aNormal') };
    this.uni = {};
    for (const u of ['uModel', 'uViewProj', 'uNormal', 'uColor', 'uLit', 'uEye', 'uLight']) this.uni[u] = gl.getUniformLocation(prog, u);
    gl.enableVertexAttribArray(this.attr.pos);
    gl.enableVertexAttribArray(this.attr.normal);
    gl.enable(gl.DEPTH_TEST);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.polygonOffset(1, 2);
    gl.uniform3fv(this.uni.uLight, v3.norm([0.4, -0.6, 1.0]));
    this.items = [];
  }

  /** Uploads a geometry; returns a handle for `add`. */
  upload(g) {
    const gl = this.gl, data = new Float32Array(g.p.length * 2);
    for (let i = 0; i < g.p.length; i++) data[2 * i - (i % 3)] = g.p[i];
    for (let i = 0; i < g.n.length; i++) data[2 * i - (i % 3) + 3] = g.n[i];
    const buffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return { buffer, count: g.count, lines: g.lines };
  }

  /**
   * Draws `geometry` every frame while `item.visible()`; `item.matrix()` is its world pose,
   * `item.color` [r, g, b, a] (or a function giving it); `depthTest` false (or a function
   * giving false) draws it over everything else.
   */
  add(geometry, item) {
    this.items.push(Object.assign({ lit: !geometry.lines, depthTest: true, visible: () => true, matrix: () => IDENTITY, order: 0 },
      item, { mesh: this.upload(geometry) }));
  }

  draw(camera, width, height, background) {
    const gl = this.gl;
    gl.viewport(0, 0, width, height);
    gl.clearColor(background[0], background[1], background[2], 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.uniformMatrix4fv(this.uni.uViewProj, false, new Float32Array(camera.viewProj));
    gl.uniform3fv(this.uni.uEye, camera.eye);
    // Opaque first, then translucent without depth writes, then what shows through.
    const value = (x) => (typeof x === 'function' ? x() : x);
    const visible = this.items.filter((it) => it.visible()).map((it) => {
      const color = value(it.color), depthTest = value(it.depthTest);
      return { it, color, depthTest, rank: (depthTest ? 0 : 2) + (color[3] < 1 ? 1 : 0) };
    }).sort((a, b) => a.rank - b.rank || a.it.order - b.it.order);
    for (const { it, color, depthTest } of visible) {
      const m = it.matrix();
      const translucent = color[3] < 1;
      gl.depthMask(!translucent);
      if (translucent) gl.enable(gl.BLEND); else gl.disable(gl.BLEND);
      if (depthTest) gl.enable(gl.DEPTH_TEST); else gl.disable(gl.DEPTH_TEST);
      // Surfaces with edges drawn on them sit a hair behind their lines.
      if (it.behindLines) gl.enable(gl.POLYGON_OFFSET_FILL); else gl.disable(gl.POLYGON_OFFSET_FILL);
      gl.uniformMatrix4fv(this.uni.uModel, false, new Float32Array(m));
      gl.uniformMatrix3fv(this.uni.uNormal, false, new Float32Array([m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]]));
      gl.uniform4fv(this.uni.uColor, color);
      gl.uniform1f(this.uni.uLit, it.lit ? 1 : 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, it.mesh.buffer);
      gl.vertexAttribPointer(this.attr.pos, 3, gl.FLOAT, false, 24, 0);
      gl.vertexAttribPointer(this.attr.normal, 3, gl.FLOAT, false, 24, 12);
      gl.drawArrays(it.mesh.lines ? gl.LINES : gl.TRIANGLES, 0, it.mesh.count);
    }
    gl.depthMask(true);
  }
}

const IDENTITY = m4.identity();

