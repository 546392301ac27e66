//! A measured object pose brought onto the support.
//!
//! A camera's pose of the part is good to a few millimetres in height and about a degree in
//! roll and pitch, but the part lies on the table whatever the camera says. [`settle`] finds the
//! resting pose nearest the measurement: the face of the part's convex hull whose outward
//! normal points most nearly down is turned, by the smallest rotation, to face straight down
//! (so yaw and position stay as measured), and the part is lowered or raised until its lowest
//! hull point is on the support plane `z = support_height`. How far that moved the part (its
//! hull centroid, about which it is turned) and turned it are reported; a measurement further
//! than the tolerance from any resting pose is refused, since it is not a part lying on the
//! table but a bad measurement.
//!
//! The result is the pose of the part *on* the support; the planner raises it by
//! `[planner] lift` to get P_init, as for a scene's `object.pose`.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pregrasp_geometry::{ConvexHull, Mesh};

/// How far a measurement may be from the resting pose it is brought to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SettleTolerance {
    /// Largest displacement of the hull's centroid (m).
    pub distance: f64,
    /// Largest rotation (rad).
    pub angle: f64,
}

impl Default for SettleTolerance {
    /// 10 mm and 5°: several times a calibrated camera's error, far below a part lying on
    /// another face.
    fn default() -> Self {
        SettleTolerance {
            distance: 0.010,
            angle: 5f64.to_radians(),
        }
    }
}

/// A measurement brought onto the support.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settled {
    /// The part's pose on the support (object → world), without the lift.
    pub pose: Isometry3<f64>,
    /// Displacement of the hull's centroid from the measured pose (m).
    pub moved: f64,
    /// Rotation from the measured pose (rad).
    pub turned: f64,
}

/// Why a measurement cannot be settled.
#[derive(Debug, thiserror::Error)]
pub enum SettleError {
    #[error(
        "the measured pose is {:.1} mm and {:.2}° from the nearest resting pose on the support \
         (at most {:.1} mm and {:.1}° are taken as measurement error): check the measurement",
        moved * 1e3, turned.to_degrees(), tolerance.distance * 1e3, tolerance.angle.to_degrees()
    )]
    TooFar {
        moved: f64,
        turned: f64,
        tolerance: SettleTolerance,
    },
    #[error("the part's convex hull: {0}")]
    Hull(#[from] pregrasp_geometry::HullError),
}

/// The resting pose on the support nearest `measured` (see the module documentation).
pub fn settle(
    mesh: &Mesh,
    measured: &Isometry3<f64>,
    support_height: f64,
    tolerance: &SettleTolerance,
) -> Result<Settled, SettleError> {
    let hull = ConvexHull::of_mesh(mesh)?;
    settle_on_hull(&hull, measured, support_height, tolerance)
}

/// [`settle`] on the part's convex hull (object frame) when the caller has it
/// ([`PartKnowledge::hull`](crate::context::PartKnowledge::hull)).
pub fn settle_on_hull(
    hull: &ConvexHull,
    measured: &Isometry3<f64>,
    support_height: f64,
    tolerance: &SettleTolerance,
) -> Result<Settled, SettleError> {
    let down = -Vector3::z();
    let down_in_object = measured.rotation.inverse() * down;
    let face = hull
        .faces
        .iter()
        .max_by(|a, b| {
            a.normal
                .dot(&down_in_object)
                .total_cmp(&b.normal.dot(&down_in_object))
        })
        .expect("a 3-D hull has faces");
    let normal = measured.rotation * face.normal.into_inner();
    let turn = UnitQuaternion::rotation_between(&normal, &down).unwrap_or_else(|| {
        // Only an upward normal has no shortest turn; the face pointing most nearly down never
        // points up.
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    });
    let rotation = turn * measured.rotation;
    // Turned about the hull's centroid, so that the part stays where it was measured.
    let centroid = hull
        .vertices
        .iter()
        .fold(Vector3::zeros(), |s, v| s + v.coords)
        / hull.vertices.len() as f64;
    let at = measured * nalgebra::Point3::from(centroid);
    let mut t = at.coords - rotation * centroid;
    let lowest = hull
        .vertices
        .iter()
        .map(|v| (rotation * v.coords + t).z)
        .fold(f64::INFINITY, f64::min);
    t.z += support_height - lowest;
    let pose = Isometry3::from_parts(Translation3::from(t), rotation);
    let moved = (pose * nalgebra::Point3::from(centroid) - at).norm();
    let turned = turn.angle();
    if moved > tolerance.distance || turned > tolerance.angle {
        return Err(SettleError::TooFar {
            moved,
            turned,
            tolerance: *tolerance,
        });
    }
    Ok(Settled {
        pose,
        moved,
        turned,
    })
}
