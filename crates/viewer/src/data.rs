//! The JSON document embedded in the page: the plan file as it is, plus what the browser needs
//! to draw it — the mesh, the hull's feature edges and each arm's kinematic and geometric
//! model. Everything is in metres and radians; poses are written as the plan file writes them
//! ([`PoseJson`]).

use nalgebra::Isometry3;
use pregrasp_geometry::{ConvexHull, Mesh};
use pregrasp_model::{ArmSetup, GraspKind, PlanSet};
use pregrasp_robot::{
    arm_geometry, ArmDescription, Gripper, Gripper2F85, GripperState, Joints, LinkShape, Primitive,
    UrKinematics,
};
use serde::Serialize;
use serde_json::value::RawValue;

use crate::options::ViewOptions;
use crate::Page;

/// The page no longer loads three.js; the view data's `three_version` field says `none`.
pub const THREE_VERSION: &str = "none";

/// Format tag of the embedded document.
pub const VIEW_FORMAT: &str = "pregrasp.view/1";

/// Largest number of FK cross-check configurations embedded per arm.
const MAX_FK_CHECKS: usize = 24;

/// The whole embedded document.
#[derive(Serialize)]
pub struct ViewData<'a> {
    pub format: &'static str,
    pub title: String,
    pub three_version: &'static str,
    pub options: OptionsJson,
    /// The plan file, field for field: the caller's JSON text, verbatim.
    pub plan: &'a RawValue,
    /// The part in its object frame.
    pub mesh: MeshJson,
    /// Feature edges of the part's convex hull, object frame: `[ax, ay, az, bx, by, bz]`.
    pub hull_edges: Vec<[f32; 6]>,
    /// One entry per `plan.robots` (the plan set's arms), same order.
    pub robots: Vec<RobotModelJson>,
}

#[derive(Serialize)]
pub struct OptionsJson {
    pub initial_plan: usize,
    pub speed: f64,
    pub autoplay: bool,
}

/// Triangle mesh as flat arrays (three.js `BufferGeometry` layout). Coordinates are stored
/// as `f32`: ~0.1 µm at a metre, far below what a screen shows, and half the text.
#[derive(Serialize)]
pub struct MeshJson {
    pub positions: Vec<f32>,
    pub indices: Vec<u32>,
}

/// What the page needs to draw one arm.
#[derive(Serialize)]
pub struct RobotModelJson {
    pub name: String,
    pub model: String,
    /// False for a robot the page cannot draw (an arm from a robot description that could
    /// not be loaded); the page then draws no arm.
    pub known: bool,
    pub dh: DhJson,
    /// An arm from its robot description: its chain steps, which the page's FK uses instead
    /// of `dh`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chain: Option<ChainJson>,
    /// Link shapes in their DH frames (`frame` indexes frames 0..=6 of the FK).
    pub links: Vec<ShapeJson>,
    pub gripper: GripperShapesJson,
    /// Configurations with Rust's flange pose (arm base frame), for the page's FK self-check.
    pub fk_check: Vec<FkCheckJson>,
}

/// Standard DH rows: link i transform is `Rz(q_i)·Tz(d_i)·Tx(a_i)·Rx(alpha_i)`.
#[derive(Serialize, Default)]
pub struct DhJson {
    pub d: [f64; 6],
    pub a: [f64; 6],
    pub alpha: [f64; 6],
}

/// The gripper's shapes open, fully closed, and closed at the widths this arm grasps with in
/// the plans (the width it closes on at the support grasp G_s and at its power grasp).
#[derive(Serialize, Default)]
pub struct GripperShapesJson {
    pub open: Vec<ShapeJson>,
    pub closed: Vec<ShapeJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_precision: Option<Vec<ShapeJson>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_power: Option<Vec<ShapeJson>>,
}

/// A pose as the plan file writes it: translation and quaternion `[x, y, z, w]`, with `w ≥ 0`
/// so that equal rotations are written equally.
#[derive(Serialize, Debug, Clone, Copy, PartialEq)]
pub struct PoseJson {
    pub xyz: [f64; 3],
    pub quat_xyzw: [f64; 4],
}

impl From<&Isometry3<f64>> for PoseJson {
    fn from(pose: &Isometry3<f64>) -> Self {
        let (xyz, quat_xyzw) = pregrasp_model::pose_numbers(pose);
        PoseJson { xyz, quat_xyzw }
    }
}

#[derive(Serialize)]
pub struct FkCheckJson {
    pub q: Joints,
    pub flange: PoseJson,
}

/// A link or gripper primitive in the DH frame `frame`.
#[derive(Serialize, Debug, Clone, PartialEq)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum ShapeJson {
    Capsule {
        name: String,
        frame: usize,
        a: [f64; 3],
        b: [f64; 3],
        radius: f64,
    },
    Cuboid {
        name: String,
        frame: usize,
        pose: PoseJson,
        half_extents: [f64; 3],
    },
    /// A flat-ended cylinder: `a`, `b` are the centres of its end faces.
    Cylinder {
        name: String,
        frame: usize,
        a: [f64; 3],
        b: [f64; 3],
        radius: f64,
    },
    /// A convex piece of a link from a robot description: its hull's vertices and outward
    /// counter-clockwise triangles.
    Hull {
        name: String,
        frame: usize,
        positions: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
    },
}

impl ShapeJson {
    /// The convex hull of `points` (in frame `frame`) as a drawn piece named `name`; `None`
    /// when they span no volume.
    fn hull(name: &str, frame: usize, points: &[nalgebra::Point3<f64>]) -> Option<ShapeJson> {
        let hull = ConvexHull::from_points(points).ok()?;
        Some(ShapeJson::Hull {
            name: name.to_string(),
            frame,
            positions: hull.vertices.iter().map(|v| v.coords.into()).collect(),
            triangles: hull.triangles,
        })
    }
}

impl From<&LinkShape> for ShapeJson {
    fn from(s: &LinkShape) -> Self {
        match &s.primitive {
            Primitive::Capsule(c) => ShapeJson::Capsule {
                name: s.name.to_string(),
                frame: s.frame,
                a: c.a.coords.into(),
                b: c.b.coords.into(),
                radius: c.radius,
            },
            Primitive::Cylinder(c) => ShapeJson::Cylinder {
                name: s.name.to_string(),
                frame: s.frame,
                a: c.a.coords.into(),
                b: c.b.coords.into(),
                radius: c.radius,
            },
            Primitive::Cuboid { pose, half_extents } => ShapeJson::Cuboid {
                name: s.name.to_string(),
                frame: s.frame,
                pose: PoseJson::from(pose),
                half_extents: (*half_extents).into(),
            },
        }
    }
}

impl<'a> ViewData<'a> {
    /// Collects everything the page draws. The hull is `hull` when the caller has it (the
    /// planner's, in the object frame), else recomputed from the mesh; a degenerate mesh simply
    /// has no feature edges.
    pub fn new(page: &Page<'a>, hull: Option<&ConvexHull>, options: &ViewOptions) -> ViewData<'a> {
        let set = page.set;
        ViewData {
            format: VIEW_FORMAT,
            title: page_title(page, options),
            three_version: THREE_VERSION,
            options: OptionsJson {
                initial_plan: options.initial_plan,
                speed: options.speed,
                autoplay: options.autoplay,
            },
            plan: page.plan_json,
            mesh: mesh_json(page.mesh),
            hull_edges: match hull {
                Some(hull) => feature_edges(hull),
                None => hull_edges(page.mesh),
            },
            robots: set
                .arms
                .iter()
                .enumerate()
                .map(|(i, a)| {
                    let gripper = match page.grippers.and_then(|g| g.get(i)) {
                        Some(g) => g.clone(),
                        None => gripper_of(a),
                    };
                    let arm = page.arms.and_then(|arms| arms.get(i));
                    robot_model(set, i, arm, &gripper)
                })
                .collect(),
        }
    }
}

/// `options.title`, else the page's own (the caller's: the scene name, or the scene file).
pub fn page_title(page: &Page<'_>, options: &ViewOptions) -> String {
    options
        .title
        .clone()
        .unwrap_or_else(|| page.title.to_string())
}

fn mesh_json(mesh: &Mesh) -> MeshJson {
    MeshJson {
        positions: mesh
            .vertices
            .iter()
            .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
            .collect(),
        indices: mesh.triangles.iter().flatten().copied().collect(),
    }
}

/// The hull's feature edges (merged coplanar faces, so no flat-face diagonals).
pub fn hull_edges(mesh: &Mesh) -> Vec<[f32; 6]> {
    match ConvexHull::of_mesh(mesh) {
        Ok(hull) => feature_edges(&hull),
        Err(_) => Vec::new(),
    }
}

/// `hull`'s feature edges as `[ax, ay, az, bx, by, bz]`.
fn feature_edges(hull: &ConvexHull) -> Vec<[f32; 6]> {
    hull.feature_edges
        .iter()
        .map(|&[i, j]| {
            let (a, b) = (hull.vertices[i], hull.vertices[j]);
            [a.x, a.y, a.z, b.x, b.y, b.z].map(|v| v as f32)
        })
        .collect()
}

/// The 2F-85 as the plan configures it (precision and power points on flange z): the gripper
/// drawn when the arm's own could not be loaded.
pub fn gripper_of(arm: &ArmSetup) -> Gripper {
    Gripper2F85 {
        precision_point_z: arm.precision_point.translation.vector.z,
        power_point_z: arm.power_point.translation.vector.z,
    }
    .into()
}

/// The page's model of arm `index` of `set`; `arm` is its description, when loaded.
fn robot_model(
    set: &PlanSet,
    index: usize,
    arm: Option<&ArmDescription>,
    gripper: &Gripper,
) -> RobotModelJson {
    let robot = &set.arms[index];
    let shapes = |state| gripper_shapes(gripper, state);
    // The fingers this robot holds the part with, as the plans record them.
    let held = |grasp: GraspKind| {
        set.plans
            .iter()
            .flat_map(|p| &p.segments)
            .filter(|s| s.arm == index && s.grasp == grasp)
            .find_map(|s| s.closing.held(gripper))
    };
    let grippers = GripperShapesJson {
        open: shapes(GripperState::Open),
        closed: shapes(gripper.fully_closed()),
        closed_precision: held(GraspKind::Support).map(shapes),
        closed_power: held(GraspKind::Power).map(shapes),
    };
    let Some(model) = robot.model.builtin() else {
        return match arm {
            Some(arm) => described_model(set, index, arm, grippers),
            // A description that could not be loaded: the page draws no arm.
            None => RobotModelJson {
                name: robot.name.clone(),
                model: robot.model.to_string(),
                known: false,
                dh: DhJson::default(),
                chain: None,
                links: Vec::new(),
                gripper: GripperShapesJson {
                    closed_precision: None,
                    closed_power: None,
                    ..grippers
                },
                fk_check: Vec::new(),
            },
        };
    };
    let dh = model.dh();
    let mut dh_json = DhJson::default();
    for i in 0..6 {
        let (d, a, alpha) = dh.row(i);
        dh_json.d[i] = d;
        dh_json.a[i] = a;
        dh_json.alpha[i] = alpha;
    }
    let kin = UrKinematics::new(model);
    RobotModelJson {
        name: robot.name.clone(),
        model: model.name().to_string(),
        known: true,
        dh: dh_json,
        chain: None,
        links: arm_geometry(model)
            .links
            .iter()
            .map(ShapeJson::from)
            .collect(),
        gripper: grippers,
        fk_check: fk_check_configs(set, index)
            .into_iter()
            .map(|q| FkCheckJson {
                q,
                flange: PoseJson::from(&kin.fk(&q)),
            })
            .collect(),
    }
}

/// Configurations the page re-derives by its own FK: the start, a generic fixed pose, and
/// the first and last point of each of arm `index`'s segments in the plans (capped).
fn fk_check_configs(set: &PlanSet, index: usize) -> Vec<Joints> {
    let mut qs = vec![set.arms[index].start, [0.3, -1.2, 1.5, -0.8, 1.1, 0.4]];
    let segments = set
        .plans
        .iter()
        .flat_map(|p| &p.segments)
        .filter(|s| s.arm == index);
    for seg in segments {
        qs.extend(seg.points.first().map(|p| p.q));
        qs.extend(seg.points.last().map(|p| p.q));
    }
    qs.truncate(MAX_FK_CHECKS);
    qs
}

// ---------- arms from a robot description (`robots[].model = "urdf"`) ----------
//
// The page composes their chain steps, `frame_{i+1} = frame_i · Rot(axis_i, q_i) · link_i`
// (`ArmKinematics::chain_steps`), instead of DH rows, and draws their links' convex pieces as
// triangle meshes in the frames 0..=6.

/// An arm's chain steps (see the module documentation); poses as the plan file writes them.
#[derive(Serialize, Debug, Clone, PartialEq)]
pub struct ChainJson {
    pub frame0: PoseJson,
    pub axes: [[f64; 3]; 6],
    pub links: [PoseJson; 6],
}

/// The gripper's shapes in `state` as the page draws them (flange frame): the 2F-85's boxes, a
/// jaw gripper's convex pieces (placed by the jaws' state).
fn gripper_shapes(gripper: &Gripper, state: GripperState) -> Vec<ShapeJson> {
    if gripper.jaws().is_none() {
        return gripper.shapes(state).iter().map(ShapeJson::from).collect();
    }
    let frames = gripper.shape_frames(state);
    let pieces = gripper.shape_pieces();
    let mut out = Vec::new();
    gripper.for_each_shape(state, |k, name, _| {
        let Some(p) = pieces[k] else { return };
        for piece in &p.pieces {
            let placed: Vec<_> = piece.iter().map(|v| frames[k] * v).collect();
            out.extend(ShapeJson::hull(
                name,
                pregrasp_robot::GRIPPER_FRAME,
                &placed,
            ));
        }
    });
    out
}

/// The page's model of arm `index` of `set`, an arm from its description `arm`.
fn described_model(
    set: &PlanSet,
    index: usize,
    arm: &ArmDescription,
    gripper: GripperShapesJson,
) -> RobotModelJson {
    let robot = &set.arms[index];
    let steps = arm.kin.chain_steps();
    let links = arm
        .geometry
        .links
        .iter()
        .flat_map(|l| {
            let pieces = l.pieces.map_or(&[][..], |p| &p.pieces[..]);
            pieces
                .iter()
                .filter_map(move |piece| ShapeJson::hull(l.name, l.frame, piece))
        })
        .collect();
    RobotModelJson {
        name: robot.name.clone(),
        model: robot.model.to_string(),
        known: true,
        dh: Default::default(),
        chain: Some(ChainJson {
            frame0: PoseJson::from(&steps.frame0),
            axes: steps.axes.map(|a| a.into_inner().into()),
            links: steps.links.map(|l| PoseJson::from(&l)),
        }),
        links,
        gripper,
        fk_check: fk_check_configs(set, index)
            .into_iter()
            .map(|q| FkCheckJson {
                q,
                flange: PoseJson::from(&arm.kin.fk(&q)),
            })
            .collect(),
    }
}
