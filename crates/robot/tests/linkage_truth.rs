//! The finger linkage held to the MuJoCo Menagerie model's own closings
//! (`data/gripper_truth/closing_2f85.json`, made by `tools/gripper_truth/closing.py`): for
//! every simulated row, the four joint angles MuJoCo settled at give its pad centre and pad
//! tip through our link frames (exactly), and the driver and spring-link angles alone, put
//! through [`FingerLinkage::assemble`], give its coupler and follower angles, pad centre and
//! pad tip — within what MuJoCo's soft loop closure leaves open (its pin and hinge stay
//! 0.14–0.3 mm apart under load, which the follower's lever turns into up to ~1.3 mm at the
//! pad tip).

use nalgebra::Point2;
use pregrasp_robot::{FingerConfig, FingerLinkage};
use serde_json::Value;

fn truth() -> Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/gripper_truth/closing_2f85.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn point(v: &Value) -> Point2<f64> {
    // G (x, y, z) → the finger plane (x, z).
    Point2::new(v[0].as_f64().unwrap(), v[2].as_f64().unwrap())
}

#[test]
fn the_linkage_assembles_as_the_menagerie_model_settled() {
    let l = FingerLinkage::robotiq_2f85();
    let truth = truth();
    let (mut fingers, mut worst_pos, mut worst_angle) = (0, 0.0_f64, 0.0_f64);
    let mut errors = Vec::new();
    for row in truth["rows"].as_array().unwrap() {
        if row["status"] != "simulated" {
            continue;
        }
        for (side, sign) in [("pos", 1.0), ("neg", -1.0)] {
            let f = &row["fingers"][side];
            let get = |k: &str| f[k].as_f64().unwrap();
            let cfg = l
                .assemble(get("driver_angle"), get("spring_link_angle"))
                .unwrap_or_else(|| panic!("{}: {side} does not assemble", row["id"]));
            let mirror = |p: Point2<f64>| Point2::new(sign * p.x, p.y);
            let settled = FingerConfig {
                driver: get("driver_angle"),
                coupler: get("coupler_angle"),
                spring_link: get("spring_link_angle"),
                follower: get("follower_angle"),
            };
            let exact = (mirror(settled.pad_center(&l)) - point(&f["pad_center"]))
                .norm()
                .max((mirror(settled.pad_tip(&l)) - point(&f["tip"])).norm());
            assert!(
                exact < 1e-4,
                "{}: {side}: frames off by {exact} m",
                row["id"]
            );
            let dc = (mirror(cfg.pad_center(&l)) - point(&f["pad_center"])).norm();
            let dt = (mirror(cfg.pad_tip(&l)) - point(&f["tip"])).norm();
            let da = (cfg.coupler - get("coupler_angle"))
                .abs()
                .max((cfg.follower - get("follower_angle")).abs());
            worst_pos = worst_pos.max(dc).max(dt);
            errors.push(dc.max(dt));
            worst_angle = worst_angle.max(da);
            fingers += 1;
        }
    }
    errors.sort_by(f64::total_cmp);
    let at = |q: f64| errors[((errors.len() - 1) as f64 * q) as usize] * 1e3;
    eprintln!(
        "{fingers} fingers: pad/tip error median {:.3} mm, p95 {:.3} mm, worst {:.3} mm; worst \
         coupler/follower angle {:.4} rad",
        at(0.5),
        at(0.95),
        worst_pos * 1e3,
        worst_angle
    );
    assert!(fingers > 900);
    // MuJoCo holds the loop by a soft equality constraint: it gives a little under load.
    assert!(
        at(0.5) < 0.6 && at(0.95) < 1.0,
        "median {} mm, p95 {} mm",
        at(0.5),
        at(0.95)
    );
    assert!(worst_pos < 2e-3, "{worst_pos}");
    assert!(worst_angle < 0.05, "{worst_angle}");
}

/// In free air the spring holds the coupler on its stop: [`FingerLinkage::parallel`] at the
/// driver angle MuJoCo settled at puts the pad where MuJoCo did, over the whole stroke.
#[test]
fn the_parallel_mode_closes_as_the_menagerie_model_does_in_free_air() {
    let l = FingerLinkage::robotiq_2f85();
    let truth = truth();
    let rows = truth["free_air"]["rows"].as_array().unwrap();
    assert!(rows.len() >= 20);
    let mut worst = 0.0_f64;
    for row in rows {
        let get = |k: &str| row[k].as_f64().unwrap();
        let cfg = l.parallel(get("driver_angle")).unwrap();
        let c = cfg.pad_center(&l);
        let tip = cfg.pad_tip(&l);
        let err = (c - Point2::new(get("pad_face_x"), get("pad_center_z")))
            .norm()
            .max((tip - Point2::new(get("tip_x"), get("tip_z"))).norm());
        worst = worst.max(err);
        assert!(cfg.distal_pitch().abs() < 0.05, "{row}");
    }
    eprintln!("free air: worst pad / tip error {:.3} mm", worst * 1e3);
    assert!(worst < 1e-3, "{worst}");
}

/// [`FingerLinkage`] against the poses `tools/geometry/derive_fingers.py` took from MuJoCo's
/// own kinematics with the loop closed (`data/robotiq_2f85_fingers.json`, `samples`): the same
/// joint angles and link frames, spring-held and blocked.
#[test]
fn the_linkage_matches_the_sampled_menagerie_poses() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/robotiq_2f85_fingers.json"
    );
    let json: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let l = FingerLinkage::robotiq_2f85();
    let mut count = 0;
    for mode in ["parallel", "blocked"] {
        for s in json["samples"][mode].as_array().unwrap() {
            let q: Vec<f64> = s["q"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect();
            let cfg = l.assemble(q[0], q[2]).unwrap();
            assert!((cfg.coupler - q[1]).abs() < 1e-5, "{mode} {q:?}: {cfg:?}");
            assert!((cfg.follower - q[3]).abs() < 1e-5, "{mode} {q:?}: {cfg:?}");
            let frames = cfg.link_frames(&l);
            for (k, name) in pregrasp_robot::FINGER_LINKS.iter().enumerate() {
                let want = &s["links"][name];
                let (x, z) = (want[0].as_f64().unwrap(), want[1].as_f64().unwrap());
                let o = frames[k].origin;
                assert!(
                    (o.x - x).abs() < 1e-5 && (o.y - z).abs() < 1e-5,
                    "{name}: {o} vs {x} {z}"
                );
                // Their pose angle is a turn about +y: ours, counter-clockwise in (x, z), is its negative.
                let phi = want[2].as_f64().unwrap();
                assert!(
                    (frames[k].angle + phi).abs() < 1e-5,
                    "{name}: {} vs {phi}",
                    frames[k].angle
                );
            }
            count += 1;
        }
    }
    assert!(count >= 30, "{count}");
}
