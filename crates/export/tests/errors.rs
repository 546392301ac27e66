//! What the exporter refuses, and how it writes: all files or none.

mod common;

use pregrasp_export::{export, Drawing, ExportError, Format, Options};
use pregrasp_io::plan_file::PlanStatus;
use pregrasp_model::TimelineError;

#[test]
fn a_plan_file_without_plans_is_refused() {
    let (file, mesh) = common::chair_side();
    let mut none = file.clone();
    none.status = PlanStatus::NoPlan;
    none.reason = Some("no candidate axis".into());
    none.plans.clear();
    let err =
        common::export_file(&none, 0, &Format::ALL, &Options::default(), Some(mesh)).unwrap_err();
    assert!(matches!(
        err,
        ExportError::Timeline(TimelineError::NoPlan { .. })
    ));
    let msg = err.to_string();
    assert!(
        msg.contains("no_plan") && msg.contains("no candidate axis"),
        "{msg}"
    );
}

#[test]
fn an_out_of_range_plan_index_is_refused() {
    let (file, mesh) = common::chair_side();
    let n = file.plans.len();
    let err =
        common::export_file(file, n, &Format::ALL, &Options::default(), Some(mesh)).unwrap_err();
    assert!(matches!(
        err,
        ExportError::Timeline(TimelineError::PlanIndex { index, count }) if index == n && count == n
    ));
    assert!(err.to_string().contains("out of range"));
    if n > 1 {
        // Another ranked plan exports as well.
        common::export_file(file, 1, &[Format::UrScript], &Options::default(), None).unwrap();
    }
}

#[test]
fn formats_parse_and_unknown_ones_are_refused() {
    assert_eq!(Format::parse_list("all").unwrap(), Format::ALL.to_vec());
    assert_eq!(
        Format::parse_list("gltf,csv").unwrap(),
        vec![Format::Csv, Format::Gltf]
    );
    let err = Format::parse_list("urscript,pdf").unwrap_err();
    assert!(err.to_string().contains("\"pdf\""), "{err}");
}

#[test]
fn bad_options_and_a_missing_mesh_are_refused() {
    let (file, _) = common::chair_side();
    for o in [
        Options {
            lookahead: 0.5,
            ..Options::default()
        },
        Options {
            gain: 50.0,
            ..Options::default()
        },
        Options {
            sync_out: 8,
            ..Options::default()
        },
        Options {
            rate: 0.0,
            ..Options::default()
        },
        Options {
            movej_speed: 3.0,
            ..Options::default()
        },
        Options {
            ros_prefix: "a b".into(),
            ..Options::default()
        },
    ] {
        assert!(matches!(
            common::export_file(file, 0, &[Format::Csv], &o, None),
            Err(ExportError::Option(_))
        ));
    }
    assert!(matches!(
        common::export_file(file, 0, &[Format::Gltf], &Options::default(), None),
        Err(ExportError::NoMesh)
    ));
}

#[test]
fn a_discontinuous_plan_is_refused() {
    let (file, _) = common::chair_side();
    let mut bad = file.clone();
    bad.plans[0].segments[1].points[0].q[0] += 0.1;
    let err = common::export_file(&bad, 0, &[Format::Csv], &Options::default(), None).unwrap_err();
    assert!(err.to_string().contains("rad from where"), "{err}");
}

#[test]
fn all_formats_export_deterministically() {
    let (file, mesh) = common::chair_side();
    let a = common::export_file(file, 0, &Format::ALL, &Options::default(), Some(mesh)).unwrap();
    let b = common::export_file(file, 0, &Format::ALL, &Options::default(), Some(mesh)).unwrap();
    assert_eq!(a, b);
    let names: Vec<&str> = a.iter().map(|f| f.name.as_str()).collect();
    for r in &file.robots {
        assert!(names.contains(&format!("{}.script", r.name).as_str()));
        assert!(names.contains(&format!("{}.csv", r.name).as_str()));
    }
    assert!(names.contains(&"plan.glb"));
}

/// What the plan set itself gets wrong, typed: a segment naming no arm, an arm whose name
/// cannot name a file, a drawing that does not match the arms.
#[test]
fn a_set_the_formats_cannot_take_is_refused_with_a_typed_error() {
    let (file, mesh) = common::chair_side();
    let set = file.to_model().unwrap();
    let mut stray = set.clone();
    stray.plans[0].segments[2].arm = 5;
    let err = export(&stray, 0, &[Format::Csv], &Options::default(), None).unwrap_err();
    assert!(
        matches!(
            err,
            ExportError::Timeline(TimelineError::UnknownArm { arm: 5, .. })
        ),
        "{err}"
    );
    let mut named = set.clone();
    named.arms[1].name = "a/b".into();
    let err = export(&named, 0, &[Format::Csv], &Options::default(), None).unwrap_err();
    assert!(matches!(err, ExportError::ArmName { .. }), "{err}");
    assert!(err.to_string().contains("cannot name a file"), "{err}");
    let (arms, grippers) = file.arms_and_grippers(None).unwrap();
    let drawing = Drawing {
        mesh,
        arms: &arms[..1],
        grippers: &grippers,
    };
    let err = export(
        &set,
        0,
        &[Format::Gltf],
        &Options::default(),
        Some(&drawing),
    )
    .unwrap_err();
    assert!(
        matches!(err, ExportError::Drawing { models: 1, .. }),
        "{err}"
    );
}
