//! The Robotiq 2F-85 finger data of `tools/geometry/derive_fingers.py` (MuJoCo Menagerie model):
//! every mesh vertex of a finger link lies in the union of its convex pieces, and the planar
//! linkage in `robotiq_2f85_fingers.json` (pivots, link points, loop closure) reproduces the
//! sampled poses MuJoCo computed, for the spring-held (parallel) and the blocked-proximal modes.

use nalgebra::Point3;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::ConvexPolyhedron;
use serde_json::Value;

fn load(name: &str) -> Value {
    let path = format!("{}/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn f(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

fn xyz(v: &Value) -> Point3<f64> {
    let a = v.as_array().expect("[x, y, z]");
    Point3::new(f(&a[0]), f(&a[1]), f(&a[2]))
}

fn xz(v: &Value) -> [f64; 2] {
    let a = v.as_array().expect("[x, z]");
    [f(&a[0]), f(&a[1])]
}

#[test]
fn every_finger_mesh_vertex_is_inside_its_link_pieces() {
    let fingers = load("robotiq_2f85_fingers.json");
    let vertices = load("robotiq_2f85_finger_vertices.json");
    let links = fingers["links"].as_array().unwrap();
    assert_eq!(
        links.len(),
        5,
        "driver, coupler, spring_link, follower, pad"
    );
    for link in links {
        let name = link["name"].as_str().unwrap();
        let hulls: Vec<ConvexPolyhedron> = link["pieces"]
            .as_array()
            .unwrap()
            .iter()
            .map(|piece| {
                let pts: Vec<Point3<f64>> = piece.as_array().unwrap().iter().map(xyz).collect();
                ConvexPolyhedron::from_convex_hull(&pts).expect("a piece is a solid polytope")
            })
            .collect();
        assert!(
            !hulls.is_empty() && hulls.len() <= 16,
            "{name}: {} pieces",
            hulls.len()
        );
        let verts: Vec<Point3<f64>> = vertices["links"]
            .as_array()
            .unwrap()
            .iter()
            .find(|l| l["name"] == name)
            .unwrap_or_else(|| panic!("{name}: no test vertices"))["vertices"]
            .as_array()
            .unwrap()
            .iter()
            .map(xyz)
            .collect();
        assert!(verts.len() >= 100, "{name}: too few test vertices");
        let worst = verts
            .iter()
            .map(|v| {
                hulls
                    .iter()
                    .map(|h| h.distance_to_local_point(v, true))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max);
        assert!(
            worst <= 1e-6,
            "{name}: a mesh vertex lies {:.4} mm outside the pieces",
            worst * 1e3
        );
        let excess = f(&link["excess_mm"]);
        assert!(excess <= 1.0, "{name}: excess {excess} mm");
        println!(
            "{name:12} {} piece(s), {} vertices inside, excess {excess:.2} mm (raw mesh {:.2} mm)",
            hulls.len(),
            verts.len(),
            f(&link["raw_excess_mm"])
        );
    }
}

/// Rotation about G's +y by `phi` acting on (x, z).
fn rot(phi: f64, v: [f64; 2]) -> [f64; 2] {
    let (s, c) = phi.sin_cos();
    [c * v[0] + s * v[1], -s * v[0] + c * v[1]]
}

fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// `ang(v) = atan2(-v.z, v.x)`: `rot(phi) (1, 0)` has angle `phi`.
fn ang(v: [f64; 2]) -> f64 {
    (-v[1]).atan2(v[0])
}

/// Intersection of the circles (p, rp) and (q, rq) on the side `side` of p -> q.
fn circle_meet(p: [f64; 2], rp: f64, q: [f64; 2], rq: f64, side: f64) -> [f64; 2] {
    let d = sub(q, p);
    let l = norm(d);
    let a = (rp * rp - rq * rq + l * l) / (2.0 * l);
    let h = (rp * rp - a * a).max(0.0).sqrt();
    let u = [d[0] / l, d[1] / l];
    let w = [-u[1], u[0]];
    let x = [p[0] + a * u[0] + h * w[0], p[1] + a * u[1] + h * w[1]];
    if cross(u, sub(x, p)).signum() == side {
        x
    } else {
        [p[0] + a * u[0] - h * w[0], p[1] + a * u[1] - h * w[1]]
    }
}

struct Linkage {
    a: [f64; 2],
    b: [f64; 2],
    cd: [f64; 2],
    dc: [f64; 2],
    es: [f64; 2],
    ef: [f64; 2],
    pf: [f64; 2],
    side_d: f64,
    side_e: f64,
}

impl Linkage {
    fn from_json(l: &Value) -> Linkage {
        let mut k = Linkage {
            a: xz(&l["base"]["driver_pivot"]),
            b: xz(&l["base"]["spring_link_pivot"]),
            cd: xz(&l["driver"]["coupler_joint"]),
            dc: xz(&l["coupler"]["follower_point"]),
            es: xz(&l["spring_link"]["follower_joint"]),
            ef: xz(&l["follower"]["follower_joint"]),
            pf: xz(&l["pad"]["frame_in_follower"]),
            side_d: 0.0,
            side_e: 0.0,
        };
        // Branches of the loop as assembled at q = 0 (every joint angle 0).
        let c0 = add(k.a, k.cd);
        let e0 = add(k.b, k.es);
        let d0 = sub(e0, k.ef);
        k.side_d = cross(sub(e0, c0), sub(d0, c0)).signum();
        k.side_e = cross(sub(k.b, d0), sub(e0, d0)).signum();
        k
    }

    /// Link poses `[x, z, phi]` (driver, coupler, spring_link, follower, pad) and the joint angles
    /// (coupler, follower) from the two base angles.
    fn solve(&self, driver: f64, spring: f64) -> ([[f64; 3]; 5], [f64; 2]) {
        let c = add(self.a, rot(-driver, self.cd));
        let e = add(self.b, rot(-spring, self.es));
        let d = circle_meet(c, norm(self.dc), e, norm(self.ef), self.side_d);
        let phi_c = ang(sub(d, c)) - ang(self.dc);
        let phi_f = ang(sub(d, e)) - ang([-self.ef[0], -self.ef[1]]);
        let p = add(d, rot(phi_f, self.pf));
        let poses = [
            [self.a[0], self.a[1], -driver],
            [c[0], c[1], phi_c],
            [self.b[0], self.b[1], -spring],
            [d[0], d[1], phi_f],
            [p[0], p[1], phi_f],
        ];
        (poses, [-phi_c - driver, -phi_f - spring])
    }

    /// The spring-held mode: coupler at 0, driver and coupler turn as one crank.
    fn parallel_spring(&self, driver: f64) -> f64 {
        let d = add(self.a, rot(-driver, add(self.cd, self.dc)));
        let e = circle_meet(d, norm(self.ef), self.b, norm(self.es), self.side_e);
        -(ang(sub(e, self.b)) - ang(self.es))
    }
}

fn wrap(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI) - std::f64::consts::PI
}

#[test]
fn finger_linkage_reproduces_the_menagerie_samples() {
    let fingers = load("robotiq_2f85_fingers.json");
    let lk = Linkage::from_json(&fingers["linkage"]);
    let names = ["driver", "coupler", "spring_link", "follower", "pad"];
    let face = xyz(&fingers["linkage"]["pad"]["contact_face_center"]);
    let mut worst: f64 = 0.0;
    for mode in ["parallel", "blocked"] {
        let samples = fingers["samples"][mode].as_array().unwrap();
        assert!(
            samples.len() >= if mode == "parallel" { 20 } else { 4 },
            "{mode}: samples"
        );
        for s in samples {
            let q: Vec<f64> = s["q"].as_array().unwrap().iter().map(f).collect();
            let (poses, [coupler, follower]) = lk.solve(q[0], q[2]);
            if mode == "parallel" {
                assert!(q[1].abs() < 1e-9, "parallel mode has the coupler at 0");
                worst = worst.max((lk.parallel_spring(q[0]) - q[2]).abs());
            } else {
                assert!(q[1] < 0.0, "blocked mode: the coupler leaves its limit");
            }
            worst = worst.max((wrap(coupler - q[1])).abs());
            worst = worst.max((wrap(follower - q[3])).abs());
            for (i, n) in names.iter().enumerate() {
                let want = &s["links"][n];
                for k in 0..3 {
                    let d = poses[i][k] - f(&want[k]);
                    worst = worst.max(if k == 2 { wrap(d).abs() } else { d.abs() });
                }
            }
            // pad contact-face centre from the pad pose
            let [x, z, phi] = poses[4];
            let c = add([x, z], rot(phi, [face.x, face.z]));
            let want = xz(&s["pad_center"]);
            worst = worst.max(norm(sub(c, want)));
        }
    }
    assert!(worst < 2e-5, "closed form vs samples: {worst:.2e}");
    // Against the table the planner used so far (robotiq_2f85.json): pad centre 141.6 mm open,
    // 154.7 mm where the pads meet.
    let par = fingers["samples"]["parallel"].as_array().unwrap();
    let open = xz(&par[0]["pad_center"])[1];
    assert!((open - 0.1416).abs() <= 5e-4, "open pad centre z {open}");
    let gaps: Vec<f64> = par.iter().map(|s| f(&s["gap"])).collect();
    let k = gaps
        .iter()
        .position(|&g| g <= 0.0)
        .expect("the stroke closes the pads");
    let t = gaps[k - 1] / (gaps[k - 1] - gaps[k]);
    let zc = (1.0 - t) * xz(&par[k - 1]["pad_center"])[1] + t * xz(&par[k]["pad_center"])[1];
    assert!((zc - 0.1547).abs() <= 5e-4, "closed pad centre z {zc}");
    let tip_open = f(&par[0]["tip_z"]);
    assert!((tip_open - 0.1603).abs() <= 5e-4, "open tip z {tip_open}");
    println!(
        "linkage vs samples {worst:.1e}; pad centre z open {:.2} mm, closed {:.2} mm; tip open {:.2} mm",
        open * 1e3,
        zc * 1e3,
        tip_open * 1e3
    );
}
