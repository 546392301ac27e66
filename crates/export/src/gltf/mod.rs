//! glTF 2.0 binary (`plan.glb`): both arms, their grippers, the table and the part, with one
//! animation over the whole plan time line.
//!
//! Frames: glTF is y-up, the plan z-up; the one root node `world` turns the plan's world into
//! glTF's (a −90° rotation about x), everything else is in plan coordinates (metres).
//!
//! Per arm, the node chain follows the arm's chain steps (`ArmKinematics::chain_steps`; for a
//! UR the standard DH chain): `<arm>` (the base pose times frame 0, static, carries the base
//! link shapes) → `<arm>_joint1` (rotation `Rot(axis1, q1)`, animated; `Rz(q1)` for DH) →
//! `<arm>_frame1` (static `link1`, for DH `Tz(d1)·Tx(a1)·Rx(α1)`, with the shapes that move
//! with the first joint) → `<arm>_joint2` → … → `<arm>_frame6` (the flange). So the world transform of
//! `<arm>_frame<i>` is `base · fk_frames(q)[i]`. Link shapes are a built-in arm's primitives
//! (cylinders, capsules, boxes), tessellated, or the convex pieces of an arm from its robot
//! description. The gripper hangs under the flange as several
//! nodes, `<arm>_gripper_open` and one `<arm>_gripper_<segment>` per segment that closes it
//! (fingers where that segment's closing stopped); a STEP-interpolated scale channel shows the one
//! in use (scale 1) and hides the others (scale 0) — a switch, not a motion.
//!
//! The part (`part`, its mesh in the object frame) has translation and rotation channels; the
//! table is a 2 m × 2 m × 20 mm box whose top is at `support_height`.
//!
//! Animation: one input accessor (times) shared by every channel: every plan point time, plus
//! extra keys wherever a joint would turn by more than 0.5 rad between two keys (glTF slerps
//! quaternions along the shorter arc, so a key interval must stay well below π). Joint and part
//! channels are LINEAR; consecutive quaternions are kept in the same hemisphere.

use std::collections::BTreeMap;

use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use json::Index;
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use pregrasp_model::{PlanSet, Timeline};
use pregrasp_robot::GripperState;

use crate::{Drawing, ExportError};

/// Largest joint turn (rad) between two animation keys.
pub const MAX_KEY_STEP: f64 = 0.5;

mod mesh;

use mesh::Tris;

/// The glTF document under construction and its binary chunk.
struct Builder {
    root: json::Root,
    bin: Vec<u8>,
}

fn quat(q: &UnitQuaternion<f64>) -> [f32; 4] {
    [q.i as f32, q.j as f32, q.k as f32, q.w as f32]
}

fn trans(v: &Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

impl Builder {
    fn view(
        &mut self,
        bytes: &[u8],
        target: Option<json::buffer::Target>,
    ) -> Index<json::buffer::View> {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.root.push(json::buffer::View {
            buffer: Index::new(0),
            byte_length: USize64(bytes.len() as u64),
            byte_offset: Some(USize64(offset as u64)),
            byte_stride: None,
            name: None,
            target: target.map(Valid),
            extensions: None,
            extras: Default::default(),
        })
    }

    /// An accessor of `n`-component float vectors; `bounds` adds min/max (required for
    /// positions and animation inputs).
    fn floats(
        &mut self,
        data: &[f32],
        n: usize,
        bounds: bool,
        target: Option<json::buffer::Target>,
    ) -> Index<json::Accessor> {
        let type_ = match n {
            1 => json::accessor::Type::Scalar,
            3 => json::accessor::Type::Vec3,
            4 => json::accessor::Type::Vec4,
            _ => unreachable!("component count {n}"),
        };
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes, target);
        let (min, max) = if bounds {
            let mut lo = vec![f32::INFINITY; n];
            let mut hi = vec![f32::NEG_INFINITY; n];
            for v in data.chunks(n) {
                for i in 0..n {
                    lo[i] = lo[i].min(v[i]);
                    hi[i] = hi[i].max(v[i]);
                }
            }
            (Some(serde_json::json!(lo)), Some(serde_json::json!(hi)))
        } else {
            (None, None)
        };
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64((data.len() / n) as u64),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::F32,
            )),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    fn mesh(&mut self, name: &str, t: &Tris, material: Index<json::Material>) -> Index<json::Mesh> {
        let flat: Vec<f32> = t.pos.iter().flatten().copied().collect();
        let pos = self.floats(&flat, 3, true, Some(json::buffer::Target::ArrayBuffer));
        let bytes: Vec<u8> = t.idx.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(json::buffer::Target::ElementArrayBuffer));
        let idx = self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64(t.idx.len() as u64),
            component_type: Valid(json::accessor::GenericComponentType(
                json::accessor::ComponentType::U32,
            )),
            extensions: None,
            extras: Default::default(),
            type_: Valid(json::accessor::Type::Scalar),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        });
        let mut attributes = BTreeMap::new();
        attributes.insert(Valid(json::mesh::Semantic::Positions), pos);
        self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name.to_string()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: Default::default(),
                indices: Some(idx),
                material: Some(material),
                mode: Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        })
    }

    fn material(&mut self, name: &str, rgba: [f32; 4]) -> Index<json::Material> {
        self.root.push(json::Material {
            name: Some(name.to_string()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                base_color_factor: json::material::PbrBaseColorFactor(rgba),
                metallic_factor: json::material::StrengthFactor(0.1),
                roughness_factor: json::material::StrengthFactor(0.7),
                ..Default::default()
            },
            double_sided: true,
            ..Default::default()
        })
    }

    fn node(&mut self, node: json::Node) -> Index<json::Node> {
        self.root.push(node)
    }

    fn add_child(&mut self, parent: Index<json::Node>, child: Index<json::Node>) {
        let p = &mut self.root.nodes[parent.value()];
        p.children.get_or_insert_with(Vec::new).push(child);
    }
}

fn named(name: String) -> json::Node {
    json::Node {
        name: Some(name),
        ..Default::default()
    }
}

/// The animation key times: every plan point time, refined so that no joint of either arm turns
/// more than [`MAX_KEY_STEP`] between neighbouring keys.
pub fn key_times(timeline: &Timeline) -> Vec<f64> {
    let points = timeline.point_times();
    let mut out = vec![points[0]];
    for w in points.windows(2) {
        let mut step: f64 = 0.0;
        for a in 0..timeline.arms.len() {
            let (q0, q1) = (timeline.q_at(a, w[0]), timeline.q_at(a, w[1]));
            for j in 0..6 {
                step = step.max((q1[j] - q0[j]).abs());
            }
        }
        let n = (step / MAX_KEY_STEP).ceil().max(1.0) as usize;
        for k in 1..n {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / n as f64);
        }
        out.push(w[1]);
    }
    out
}

/// The `.glb` bytes of `set`'s plan `timeline` with the part and the arms of `drawing` (one
/// description and gripper per arm of `set`, in its order).
pub fn export(
    set: &PlanSet,
    timeline: &Timeline,
    drawing: &Drawing<'_>,
) -> Result<Vec<u8>, ExportError> {
    let Drawing {
        mesh,
        arms,
        grippers,
    } = *drawing;
    if arms.len() != set.arms.len() || grippers.len() != set.arms.len() {
        return Err(ExportError::Drawing {
            models: arms.len(),
            grippers: grippers.len(),
            arms: set.arms.len(),
        });
    }
    let mut b = Builder {
        root: json::Root {
            asset: json::Asset {
                generator: Some("pregrasp export".into()),
                ..Default::default()
            },
            ..Default::default()
        },
        bin: Vec::new(),
    };
    let m_arm = b.material("arm", [0.62, 0.66, 0.72, 1.0]);
    let m_grip = b.material("gripper", [0.15, 0.15, 0.17, 1.0]);
    let m_table = b.material("table", [0.55, 0.42, 0.30, 1.0]);
    let m_part = b.material("part", [0.90, 0.55, 0.20, 1.0]);

    let world = b.node(json::Node {
        rotation: Some(json::scene::UnitQuaternion(quat(
            &UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2),
        ))),
        ..named("world".into())
    });

    // Table.
    let n_arms = set.arms.len().max(1) as f64;
    let centre = set
        .arms
        .iter()
        .fold(Vector3::zeros(), |acc, a| acc + a.base.translation.vector)
        / n_arms;
    let mut t = Tris::default();
    t.cuboid(
        &Isometry3::translation(centre.x, centre.y, timeline.support_height - 0.01),
        &Vector3::new(1.0, 1.0, 0.01),
    );
    let table_mesh = b.mesh("table", &t, m_table);
    let table = b.node(json::Node {
        mesh: Some(table_mesh),
        ..named("table".into())
    });
    b.add_child(world, table);

    // Part.
    let mut t = Tris::default();
    for v in &mesh.vertices {
        t.vertex(Point3::new(v.x, v.y, v.z));
    }
    for tri in &mesh.triangles {
        t.idx.extend(tri);
    }
    let part_mesh = b.mesh("part", &t, m_part);
    let p0 = timeline.object_at(0.0);
    let part = b.node(json::Node {
        mesh: Some(part_mesh),
        translation: Some(trans(&p0.translation.vector)),
        rotation: Some(json::scene::UnitQuaternion(quat(&p0.rotation))),
        ..named("part".into())
    });
    b.add_child(world, part);

    // Arms.
    let times = key_times(timeline);
    let input_data: Vec<f32> = times.iter().map(|x| *x as f32).collect();
    if input_data.windows(2).any(|w| w[1] <= w[0]) {
        return Err(ExportError::KeyTimes);
    }
    let input = b.floats(&input_data, 1, true, None);
    let mut channels = Vec::new();
    let mut samplers = Vec::new();
    let mut channel = |b: &mut Builder,
                       node: Index<json::Node>,
                       path: json::animation::Property,
                       data: Vec<f32>,
                       n: usize,
                       interp: json::animation::Interpolation| {
        let output = b.floats(&data, n, false, None);
        samplers.push(json::animation::Sampler {
            extensions: None,
            extras: Default::default(),
            input,
            interpolation: Valid(interp),
            output,
        });
        channels.push(json::animation::Channel {
            sampler: Index::new(samplers.len() as u32 - 1),
            target: json::animation::Target {
                extensions: None,
                extras: Default::default(),
                node,
                path: Valid(path),
            },
            extensions: None,
            extras: Default::default(),
        });
    };

    for (ai, arm) in timeline.arms.iter().enumerate() {
        let setup = &set.arms[ai];
        let geometry = &arms[ai].geometry;
        let gripper = &grippers[ai];
        let steps = arms[ai].kin.chain_steps();
        // A built-in arm's link shapes are what it looks like; an arm from a robot
        // description is drawn by its pieces (its shapes are their boxes).
        let pieces = arms[ai].ur.is_none();
        let shapes_of = |frame: usize| {
            let mut t = Tris::default();
            for l in geometry.links.iter().filter(|l| l.frame == frame) {
                t.link(l, pieces);
            }
            t
        };
        let base_mesh = b.mesh(&format!("{}_link0", arm.name), &shapes_of(0), m_arm);
        let base_pose = setup.base * steps.frame0;
        let base = b.node(json::Node {
            mesh: Some(base_mesh),
            translation: Some(trans(&base_pose.translation.vector)),
            rotation: Some(json::scene::UnitQuaternion(quat(&base_pose.rotation))),
            ..named(arm.name.clone())
        });
        b.add_child(world, base);
        let mut parent = base;
        let q_keys: Vec<[f64; 6]> = times.iter().map(|t| timeline.q_at(ai, *t)).collect();
        for j in 0..6 {
            let q0 = setup.start[j];
            let axis = steps.axes[j];
            let joint = b.node(json::Node {
                rotation: Some(json::scene::UnitQuaternion(quat(
                    &UnitQuaternion::from_axis_angle(&axis, q0),
                ))),
                ..named(format!("{}_joint{}", arm.name, j + 1))
            });
            b.add_child(parent, joint);
            let step = steps.links[j];
            let link = shapes_of(j + 1);
            let link_mesh = if link.idx.is_empty() {
                None
            } else {
                Some(b.mesh(&format!("{}_link{}", arm.name, j + 1), &link, m_arm))
            };
            let frame = b.node(json::Node {
                mesh: link_mesh,
                translation: Some(trans(&step.translation.vector)),
                rotation: Some(json::scene::UnitQuaternion(quat(&step.rotation))),
                ..named(format!("{}_frame{}", arm.name, j + 1))
            });
            b.add_child(joint, frame);
            // Rotation keys Rot(axis_j, q_j), consecutive quaternions in one hemisphere.
            let mut data = Vec::with_capacity(4 * times.len());
            let mut prev: Option<[f64; 4]> = None;
            for q in &q_keys {
                let (s, c) = (0.5 * q[j]).sin_cos();
                let mut v = [s * axis.x, s * axis.y, s * axis.z, c];
                if let Some(p) = prev {
                    if p.iter().zip(&v).map(|(a, b)| a * b).sum::<f64>() < 0.0 {
                        v = v.map(|x| -x);
                    }
                }
                // No −0 from an axis component that is zero.
                v = v.map(|x| x + 0.0);
                prev = Some(v);
                data.extend(v.map(|x| x as f32));
            }
            channel(
                &mut b,
                joint,
                json::animation::Property::Rotation,
                data,
                4,
                json::animation::Interpolation::Linear,
            );
            parent = frame;
        }
        // Grippers under the flange: open, and one per segment that closes it.
        let mut variants: Vec<(Option<usize>, GripperState)> = vec![(None, GripperState::Open)];
        for e in arm.grip.iter().filter(|e| e.close) {
            let held = e
                .fingers
                .or_else(|| e.width.map(|w| gripper.at_gap(w)))
                .unwrap_or_else(|| gripper.fully_closed());
            variants.push((Some(e.segment), held));
        }
        for (seg, state) in &variants {
            let mut t = Tris::default();
            for s in gripper.shapes(*state) {
                t.primitive(&s.primitive);
            }
            let label = match seg {
                None => "open".to_string(),
                Some(k) => timeline.segments[*k].name.to_string(),
            };
            let name = format!("{}_gripper_{label}", arm.name);
            let gm = b.mesh(&name, &t, m_grip);
            let shown_at = |time: f64| -> bool {
                let mut current: Option<usize> = None;
                for e in arm.grip.iter().filter(|e| e.t <= time) {
                    current = if e.close { Some(e.segment) } else { None };
                }
                current == *seg
            };
            let node = b.node(json::Node {
                mesh: Some(gm),
                scale: Some(if shown_at(0.0) { [1.0; 3] } else { [0.0; 3] }),
                ..named(name)
            });
            b.add_child(parent, node);
            let data: Vec<f32> = times
                .iter()
                .flat_map(|t| if shown_at(*t) { [1.0f32; 3] } else { [0.0; 3] })
                .collect();
            channel(
                &mut b,
                node,
                json::animation::Property::Scale,
                data,
                3,
                json::animation::Interpolation::Step,
            );
        }
    }

    // The part's channels.
    let poses: Vec<Isometry3<f64>> = times.iter().map(|t| timeline.object_at(*t)).collect();
    let tr: Vec<f32> = poses
        .iter()
        .flat_map(|p| trans(&p.translation.vector))
        .collect();
    let mut rot = Vec::with_capacity(4 * poses.len());
    let mut prev: Option<UnitQuaternion<f64>> = None;
    for p in &poses {
        let mut q = p.rotation;
        if let Some(pq) = prev {
            if pq.coords.dot(&q.coords) < 0.0 {
                q = UnitQuaternion::new_unchecked(-q.into_inner());
            }
        }
        prev = Some(q);
        rot.extend(quat(&q));
    }
    channel(
        &mut b,
        part,
        json::animation::Property::Translation,
        tr,
        3,
        json::animation::Interpolation::Linear,
    );
    channel(
        &mut b,
        part,
        json::animation::Property::Rotation,
        rot,
        4,
        json::animation::Interpolation::Linear,
    );
    b.root.push(json::Animation {
        extensions: None,
        extras: Default::default(),
        channels,
        name: Some("plan".into()),
        samplers,
    });
    let scene = b.root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: Some("pregrasp plan".into()),
        nodes: vec![world],
    });
    b.root.scene = Some(scene);
    while b.bin.len() % 4 != 0 {
        b.bin.push(0);
    }
    b.root.push(json::Buffer {
        byte_length: USize64(b.bin.len() as u64),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let mut text = b
        .root
        .to_vec()
        .map_err(|e| ExportError::Gltf(e.to_string()))?;
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    Ok(glb(&text, &b.bin))
}

/// GLB framing: 12-byte header, a JSON chunk and a BIN chunk (both 4-byte aligned).
fn glb(json_chunk: &[u8], bin: &[u8]) -> Vec<u8> {
    let total = 12 + 8 + json_chunk.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json_chunk);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out
}
