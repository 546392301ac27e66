//! Real furniture stock: the three example families at 18–40 mm thick with 25–60 mm bars, the
//! support pinch's fingertips 3 mm above the table. Every scene plans, every plan passes the
//! checker, and no grasping gripper comes closer to the table than the finger–support
//! clearance (issue 11).

use pregrasp_examples::{with_design, ChairSideParams, ShelfSideParams, StoolSideParams};
use pregrasp_io::plan_file::PlanStatus;
use pregrasp_io::scene::Scene;
use pregrasp_planner::check::check_plan;
use pregrasp_planner::pipeline::{plan, PlanOptions};

const STOCK: [f64; 5] = [0.018, 0.022, 0.025, 0.030, 0.040];
const BARS: [f64; 3] = [0.025, 0.040, 0.060];

fn design(family: &str, thickness: f64, bar: f64) -> pregrasp_examples::PartDesign {
    match family {
        "chair_side" => ChairSideParams {
            thickness,
            front_leg_width: bar,
            back_leg_width: bar,
            seat_rail_width: bar,
            stretcher_width: bar,
            ..ChairSideParams::default()
        }
        .design(),
        "shelf_side" => ShelfSideParams {
            thickness,
            handle_bar_width: bar,
            ..ShelfSideParams::default()
        }
        .design(),
        "stool_side" => StoolSideParams {
            thickness,
            leg_width: bar,
            top_rail_width: bar,
            stretcher_width: bar,
            ..StoolSideParams::default()
        }
        .design(),
        _ => unreachable!(),
    }
}

#[test]
fn real_stock_plans_and_passes_the_check_for_every_family() {
    let mut failures = Vec::new();
    let mut planned = 0;
    for family in ["chair_side", "shelf_side", "stool_side"] {
        for thickness in STOCK {
            for bar in BARS {
                let label = format!(
                    "{family} {:.0} mm stock, {:.0} mm bars",
                    thickness * 1e3,
                    bar * 1e3
                );
                let example = with_design(family, design(family, thickness, bar)).unwrap();
                let scene =
                    Scene::from_str(&example.scene_toml, std::path::Path::new("sweep.toml"))
                        .unwrap_or_else(|e| panic!("{label}: {e}"));
                let report = plan(
                    &scene,
                    &example.mesh,
                    &PlanOptions::default(),
                    &|_| {},
                    &|| {},
                )
                .unwrap();
                let file = report.file;
                if file.status != PlanStatus::Planned {
                    failures.push(format!("{label}: {}", file.reason.unwrap_or_default()));
                    continue;
                }
                planned += 1;
                let check = check_plan(&file, &example.mesh);
                assert!(check.is_valid(), "{label}: {:?}", check.rules);
                let clearance = scene.planner.finger_support_clearance;
                let closest = check.closest_grasp_to_support.expect("states were checked");
                assert!(
                    closest >= clearance,
                    "{label}: a grasping gripper came {:.2} mm from the table",
                    closest * 1e3
                );
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{planned} planned; refused:\n{}",
        failures.join("\n")
    );
}

/// A scene that declares the true pad centre of its pinch as the precision point (the pads'
/// depth at the width of the support bar, from the finger linkage) does no worse than one that
/// keeps the default 0.150: with the same G_s its flange sits higher, so its fingertips keep
/// at least as much room above the table.
#[test]
fn declaring_the_true_pad_centre_never_does_worse() {
    let fingers = pregrasp_robot::FingerKinematics::robotiq_2f85();
    for family in ["chair_side", "shelf_side", "stool_side"] {
        let example = pregrasp_examples::by_name(family).unwrap();
        let path = std::path::Path::new("pad_centre.toml");
        let default = Scene::from_str(&example.scene_toml, path).unwrap();
        let mut declared = default.clone();
        let pad_centre = fingers.at(example.design.support.bar_width).pad_center_z;
        assert!(
            pad_centre > 0.150,
            "{family}: the pads sit deeper than the default point"
        );
        for robot in &mut declared.robots {
            robot.precision_point_z = pad_centre;
        }
        let closest = |scene: &Scene| {
            let file = plan(
                scene,
                &example.mesh,
                &PlanOptions::default(),
                &|_| {},
                &|| {},
            )
            .unwrap()
            .file;
            assert_eq!(
                file.status,
                PlanStatus::Planned,
                "{family}: {:?}",
                file.reason
            );
            let check = check_plan(&file, &example.mesh);
            assert!(check.is_valid(), "{family}: {:?}", check.rules);
            check.closest_grasp_to_support.unwrap()
        };
        let (d_default, d_declared) = (closest(&default), closest(&declared));
        assert!(
            d_declared >= d_default - 1e-9,
            "{family}: {d_declared} m with the true pad centre, {d_default} m with the default"
        );
    }
}
