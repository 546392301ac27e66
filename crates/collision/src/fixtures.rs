//! Small mesh builders and poses for tests, benchmarks and the reach-problem generator.
//!
//! All meshes are closed, triangles counter-clockwise seen from outside, metres.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use pregrasp_geometry::Mesh;
use pregrasp_robot::{Gripper2F85, GripperState, Joints, UrModel};

use crate::{ArmModel, CollisionWorld};

/// A UR arm upright: shoulder lifted, elbow bent, the wrist's tool pointing down.
pub const UP: Joints = [0.0, -FRAC_PI_2, FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2, 0.0];

/// Joint ranges (rad, `[lo, hi)`) random configurations of a UR arm are drawn from in the
/// tests of [`two_arm_cell`]: shoulder up, elbow bent, wrist anywhere.
pub const SAMPLE_RANGES: [(f64, f64); 6] = [
    (-PI, PI),
    (-2.8, -0.3),
    (-2.5, 2.5),
    (-PI, PI),
    (-PI, PI),
    (-PI, PI),
];

/// Flange pose (arm base frame) with the tool pointing down, the 2F-85's precision point
/// `height` above the top (z = 0.02) of [`plate_10k`] at `(x, y)`, turned by `yaw` about the
/// vertical.
pub fn stand_off(x: f64, y: f64, height: f64, yaw: f64) -> Isometry3<f64> {
    let top = 0.02;
    let g = Gripper2F85::default();
    let rot = UnitQuaternion::from_euler_angles(0.0, 0.0, yaw)
        * UnitQuaternion::from_euler_angles(PI, 0.0, 0.0);
    Isometry3::from_parts(
        Translation3::new(x, y, top + height + g.precision_point_z),
        rot,
    )
}

/// An axis-aligned box `center ± half` subdivided into `n × n` quads per face
/// (`12 n²` triangles; `n = 1` is the plain 12-triangle box).
pub fn box_mesh(center: Point3<f64>, half: Vector3<f64>, n: usize) -> Mesh {
    let n = n.max(1);
    let mut mesh = Mesh::default();
    // Each face: a normal axis `k` and sign, spanned by the two other axes (u, v) ordered
    // so that u × v points outwards.
    for k in 0..3 {
        for sign in [-1.0, 1.0] {
            let (mut u, mut v) = ((k + 1) % 3, (k + 2) % 3);
            if sign < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            let base = mesh.vertices.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let mut p = [0.0; 3];
                    p[k] = center[k] + sign * half[k];
                    p[u] = center[u] - half[u] + 2.0 * half[u] * i as f64 / n as f64;
                    p[v] = center[v] - half[v] + 2.0 * half[v] * j as f64 / n as f64;
                    mesh.vertices.push(Point3::from(p));
                }
            }
            let id = |i: usize, j: usize| base + (i * (n + 1) + j) as u32;
            for i in 0..n {
                for j in 0..n {
                    mesh.triangles
                        .push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                    mesh.triangles
                        .push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
    }
    mesh
}

/// Concatenates meshes (vertex indices re-based).
pub fn merge(meshes: &[Mesh]) -> Mesh {
    let mut out = Mesh::default();
    for m in meshes {
        let base = out.vertices.len() as u32;
        out.vertices.extend_from_slice(&m.vertices);
        out.triangles.extend(
            m.triangles
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    out
}

/// A flat rectangular frame lying in the `xy` plane, centred at the origin: outer size
/// `outer_x × outer_y`, bars `bar` wide, `thickness` thick (`z ∈ [0, thickness]`).
/// The opening is `(outer_x − 2 bar) × (outer_y − 2 bar)`. Four boxes (48 triangles).
pub fn frame_mesh(outer_x: f64, outer_y: f64, bar: f64, thickness: f64) -> Mesh {
    let hz = 0.5 * thickness;
    let (hx, hy) = (0.5 * outer_x, 0.5 * outer_y);
    let hb = 0.5 * bar;
    merge(&[
        // Bars along x at y = ±(hy − hb), full length.
        box_mesh(Point3::new(0.0, hy - hb, hz), Vector3::new(hx, hb, hz), 1),
        box_mesh(
            Point3::new(0.0, -(hy - hb), hz),
            Vector3::new(hx, hb, hz),
            1,
        ),
        // Bars along y at x = ±(hx − hb), between the x bars.
        box_mesh(
            Point3::new(hx - hb, 0.0, hz),
            Vector3::new(hb, hy - bar, hz),
            1,
        ),
        box_mesh(
            Point3::new(-(hx - hb), 0.0, hz),
            Vector3::new(hb, hy - bar, hz),
            1,
        ),
    ])
}

/// A `0.6 × 0.4 × 0.02` m plate (`z ∈ [0, 0.02]`, centred in `xy`) with 10 092 triangles:
/// the "10k-triangle part" of the benchmarks.
pub fn plate_10k() -> Mesh {
    box_mesh(
        Point3::new(0.0, 0.0, 0.01),
        Vector3::new(0.3, 0.2, 0.01),
        29,
    )
}

/// Two UR5e side by side 0.9 m apart (bases at `y = ±0.45`, "left" and "right"), a
/// [`frame_mesh`] part (0.5 × 0.3 m, 5 cm bars, 2 cm thick) between them on a support at
/// `z = 0`, the planner's margins, each gripper holding its fingers 2 cm apart when it grasps.
pub fn two_arm_cell() -> CollisionWorld {
    let arm = |name: &str, y: f64| {
        let base = Isometry3::translation(0.0, y, 0.0);
        ArmModel::new(name, UrModel::Ur5e, base, Gripper2F85::default())
    };
    let mesh = frame_mesh(0.5, 0.3, 0.05, 0.02);
    CollisionWorld::try_new(
        Some(0.0),
        Some(&mesh),
        [arm("left", 0.45), arm("right", -0.45)],
    )
    .expect("a valid mesh")
    .with_margin(0.008)
    .with_grasp_support_margin(0.0026)
    .with_held_fingers([&[GripperState::at_gap(0.02)], &[GripperState::at_gap(0.02)]])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Signed volume by the divergence theorem: positive iff faces point outwards.
    fn volume(m: &Mesh) -> f64 {
        m.triangles
            .iter()
            .map(|t| {
                let (a, b, c) = (
                    m.vertices[t[0] as usize],
                    m.vertices[t[1] as usize],
                    m.vertices[t[2] as usize],
                );
                a.coords.dot(&b.coords.cross(&c.coords)) / 6.0
            })
            .sum()
    }

    #[test]
    fn subdivided_box_is_closed_outward_with_exact_volume() {
        let m = box_mesh(Point3::new(0.1, -0.2, 0.3), Vector3::new(0.3, 0.2, 0.1), 3);
        assert_eq!(m.triangles.len(), 12 * 9);
        assert!((volume(&m) - 0.6 * 0.4 * 0.2).abs() < 1e-12);
    }

    #[test]
    fn plate_has_ten_thousand_triangles() {
        let m = plate_10k();
        assert_eq!(m.triangles.len(), 10_092);
        assert!((volume(&m) - 0.6 * 0.4 * 0.02).abs() < 1e-12);
    }

    #[test]
    fn frame_volume_is_outer_minus_opening() {
        let m = frame_mesh(0.5, 0.4, 0.05, 0.02);
        let expect = (0.5 * 0.4 - 0.4 * 0.3) * 0.02;
        assert!((volume(&m) - expect).abs() < 1e-12);
    }
}
