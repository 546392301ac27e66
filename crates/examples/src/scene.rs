//! Scene files for the built-in examples (`docs/scene-format.md`): two UR5e arms on
//! one table and a part lying flat between them, placed so its intended axis faces the arms.

use std::fmt::Write as _;

use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion, Vector3};

use crate::design::{GraspSite, PartDesign};

/// Density used for the parts' `mass` (kg/m³): beech or oak, air-dried.
pub const WOOD_DENSITY: f64 = 700.0;

/// One arm of a scene (base pose is a translation in the table plane; models are "ur5e").
#[derive(Clone, Debug, PartialEq)]
pub struct ArmSetup {
    pub name: &'static str,
    /// Base position in world (m); the base frame is not rotated.
    pub base_xyz: [f64; 3],
    /// Start configuration (rad).
    pub start: [f64; 6],
}

/// Where the part lies on the table and where the arms stand.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLayout {
    /// World `x` of the intended axis line (m): the part extends from it towards `+x`, away
    /// from the arms, so that once tilted up its top face looks at the arms.
    pub axis_x: f64,
    /// World `y` of the middle of the part's extent along the axis (m).
    pub centre_y: f64,
    /// `robot[0]` ("left", `y > 0`) and `robot[1]` ("right").
    pub arms: [ArmSetup; 2],
}

impl Default for SceneLayout {
    fn default() -> Self {
        // Home: upper arm up, forearm forward over the table towards +x, tool pointing down.
        let (pi, half_pi) = (std::f64::consts::PI, std::f64::consts::FRAC_PI_2);
        let start = [pi, -1.8, 1.8, -half_pi, -half_pi, 0.0];
        Self {
            axis_x: 0.27,
            centre_y: 0.0,
            arms: [
                ArmSetup {
                    name: "left",
                    base_xyz: [0.0, 0.45, 0.0],
                    start,
                },
                ArmSetup {
                    name: "right",
                    base_xyz: [0.0, -0.45, 0.0],
                    start,
                },
            ],
        }
    }
}

/// Round to `decimals` places, turning `-0` into `0` so files read cleanly.
fn round(x: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    let r = (x * s).round() / s;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// The object's pose P (object frame in world, before the lift): yaw about world `z` so the
/// axis's inward normal points along world `+x`, the axis line at `x = layout.axis_x`, the
/// part's extent along the axis centred on `layout.centre_y`, its bottom face on the table.
/// The yaw is rounded to 0.01° and the translation to 0.1 mm, as written in the scene file.
pub fn object_pose(design: &PartDesign, layout: &SceneLayout) -> Isometry3<f64> {
    let yaw_deg = object_yaw_deg(design);
    let rotation = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw_deg.to_radians());
    let turned = |p: &Point2<f64>| rotation * nalgebra::Point3::new(p.x, p.y, 0.0);
    let axis_x = turned(&design.axis[0]).x;
    let ys = design.outline.iter().map(|p| turned(p).y);
    let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| {
        (lo.min(y), hi.max(y))
    });
    let tx = round(layout.axis_x - axis_x, 4);
    let ty = round(layout.centre_y - (lo + hi) / 2.0, 4);
    Isometry3::from_parts(Translation3::new(tx, ty, 0.0), rotation)
}

/// The object's yaw (degrees, rounded to 0.01°) that turns the axis's inward normal to `+x`.
fn object_yaw_deg(design: &PartDesign) -> f64 {
    let n = design.axis_inward_normal();
    round(-n.y.atan2(n.x).to_degrees(), 2)
}

/// The two power grasps in `robot[0]`, `robot[1]` order: the one lying at larger world `y`
/// (on the left arm's side) first.
pub fn power_grasps_by_arm<'a>(
    design: &'a PartDesign,
    pose: &Isometry3<f64>,
) -> [&'a GraspSite; 2] {
    let world_y = |s: &GraspSite| (pose * nalgebra::Point3::new(s.point.x, s.point.y, 0.0)).y;
    let (near, far) = (&design.power_near, &design.power_far);
    if world_y(near) >= world_y(far) {
        [near, far]
    } else {
        [far, near]
    }
}

fn fmt_vec(v: &[f64], decimals: usize) -> String {
    let items: Vec<String> = v
        .iter()
        .map(|x| format!("{:.*}", decimals, round(*x, decimals as i32)))
        .collect();
    format!("[{}]", items.join(", "))
}

fn fmt_grasp(design: &PartDesign, site: &GraspSite) -> String {
    // R = Rz(closing_angle) · Rx(π), exactly the `rpy` convention of the scene format.
    let t = design.grasp_pose(site).translation.vector;
    let yaw = site.closing_angle.to_degrees();
    let yaw = if yaw > 180.0 {
        yaw - 360.0
    } else if yaw <= -180.0 {
        yaw + 360.0
    } else {
        yaw
    };
    format!(
        "{{ xyz = {}, rpy_deg = {} }}",
        fmt_vec(&[t.x, t.y, t.z], 4),
        fmt_vec(&[180.0, 0.0, yaw], 2)
    )
}

/// The scene file text (TOML) for `design` laid out by `layout`; `mesh` is the mesh path
/// relative to the scene file. Deterministic: same input, same bytes.
pub fn scene_toml(
    name: &str,
    title: &str,
    mesh: &str,
    design: &PartDesign,
    layout: &SceneLayout,
) -> String {
    let pose = object_pose(design, layout);
    let t = pose.translation.vector;
    let yaw = object_yaw_deg(design);
    let mass = design.face_area() * design.thickness * WOOD_DENSITY;
    let power = power_grasps_by_arm(design, &pose);
    let role = |s: &GraspSite| {
        if std::ptr::eq(s, &design.power_near) {
            "nearer the axis: supportive arm"
        } else {
            "farther from the axis: master arm"
        }
    };
    let dist = |s: &GraspSite| design.distance_to_axis(&s.point);
    let mut out = String::new();
    let w = &mut out;
    let _ = writeln!(
        w,
        "# {name}.toml, {title}: built-in example of pregrasp (`pregrasp example write`)."
    );
    let _ = writeln!(
        w,
        "# Generated by crates/examples; edit the generator, not this file."
    );
    let _ = writeln!(
        w,
        "# Intended rotation axis (object frame, bottom face): [{:.4}, {:.4}, 0] - [{:.4}, {:.4}, 0].",
        design.axis[0].x, design.axis[0].y, design.axis[1].x, design.axis[1].y
    );
    let _ = writeln!(w, "name = \"{title}\"\n");
    let _ = writeln!(w, "[support]\nheight = 0.0\n");
    let _ = writeln!(w, "[object]\nmesh = \"{mesh}\"\nscale = 1.0");
    let _ = writeln!(
        w,
        "pose = {{ xyz = {}, rpy_deg = {} }}",
        fmt_vec(&[t.x, t.y, t.z], 4),
        fmt_vec(&[0.0, 0.0, yaw], 2)
    );
    let _ = writeln!(
        w,
        "mass = {:.2}    # kg, wood at {WOOD_DENSITY} kg/m^3\n",
        mass
    );
    let _ = writeln!(
        w,
        "[grasps]    # object frame; grasp z along object -z, fingers closing across the bar"
    );
    let _ = writeln!(w, "power = [");
    for (i, site) in power.iter().enumerate() {
        let _ = writeln!(
            w,
            "  # G_p{} (robot[{i}]): {}, {:.3} m from the axis ({})",
            i + 1,
            site.bar,
            dist(site),
            role(site)
        );
        let _ = writeln!(w, "  {},", fmt_grasp(design, site));
    }
    let _ = writeln!(w, "]");
    let _ = writeln!(
        w,
        "# G_s: precision grasp on the {}, {:.3} m from the axis",
        design.support.bar,
        dist(&design.support)
    );
    let _ = writeln!(w, "support = {}", fmt_grasp(design, &design.support));
    for arm in &layout.arms {
        let _ = writeln!(w, "\n[[robot]]\nname = \"{}\"\nmodel = \"ur5e\"", arm.name);
        let _ = writeln!(w, "base = {{ xyz = {} }}", fmt_vec(&arm.base_xyz, 3));
        let _ = writeln!(w, "start = {}", fmt_vec(&arm.start, 4));
        let _ = writeln!(w, "gripper = \"robotiq_2f85\"");
        let _ = writeln!(
            w,
            "power_point_z = {:.3}    # palm + half the part's thickness + 4 mm",
            design.power_point_z()
        );
    }
    let _ = writeln!(w, "\n[planner]    # the defaults of scene-format.md");
    out
}
