//! What the exporter refuses, and how it writes: all files or none.

mod common;

use pregrasp_export::{export, write_all, ExportError, Format, Options, OutFile};
use pregrasp_io::plan_file::PlanStatus;

#[test]
fn a_plan_file_without_plans_is_refused() {
    let (file, mesh) = common::chair_side();
    let mut none = file.clone();
    none.status = PlanStatus::NoPlan;
    none.reason = Some("no candidate axis".into());
    none.plans.clear();
    let err = export(&none, 0, &Format::ALL, &Options::default(), Some(mesh)).unwrap_err();
    assert!(matches!(err, ExportError::NoPlan { .. }));
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
    let err = export(file, n, &Format::ALL, &Options::default(), Some(mesh)).unwrap_err();
    assert!(matches!(err, ExportError::PlanIndex { index, count } if index == n && count == n));
    assert!(err.to_string().contains("out of range"));
    if n > 1 {
        // Another ranked plan exports as well.
        export(file, 1, &[Format::UrScript], &Options::default(), None).unwrap();
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
            export(file, 0, &[Format::Csv], &o, None),
            Err(ExportError::Option(_))
        ));
    }
    assert!(matches!(
        export(file, 0, &[Format::Gltf], &Options::default(), None),
        Err(ExportError::NoMesh)
    ));
}

#[test]
fn a_discontinuous_plan_is_refused() {
    let (file, _) = common::chair_side();
    let mut bad = file.clone();
    bad.plans[0].segments[1].points[0].q[0] += 0.1;
    let err = export(&bad, 0, &[Format::Csv], &Options::default(), None).unwrap_err();
    assert!(err.to_string().contains("rad from where"), "{err}");
}

#[test]
fn all_formats_export_deterministically_and_write_all_or_nothing() {
    let (file, mesh) = common::chair_side();
    let a = export(file, 0, &Format::ALL, &Options::default(), Some(mesh)).unwrap();
    let b = export(file, 0, &Format::ALL, &Options::default(), Some(mesh)).unwrap();
    assert_eq!(a, b);
    let names: Vec<&str> = a.iter().map(|f| f.name.as_str()).collect();
    for r in &file.robots {
        assert!(names.contains(&format!("{}.script", r.name).as_str()));
        assert!(names.contains(&format!("{}.csv", r.name).as_str()));
    }
    assert!(names.contains(&"plan.glb"));
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let written = write_all(&out, &a, &[]).unwrap();
    assert_eq!(written.len(), a.len());
    for f in &a {
        assert_eq!(std::fs::read(out.join(&f.name)).unwrap(), f.bytes);
    }
    // A target that cannot be written: nothing else is written, no temporary file is left.
    let out2 = tmp.path().join("out2");
    std::fs::create_dir_all(out2.join("b.csv")).unwrap();
    let files = vec![
        OutFile {
            name: "a.csv".into(),
            bytes: b"x".to_vec(),
        },
        OutFile {
            name: "b.csv".into(),
            bytes: b"y".to_vec(),
        },
    ];
    assert!(write_all(&out2, &files, &[]).is_err());
    let left: Vec<String> = std::fs::read_dir(&out2)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        left,
        vec!["b.csv".to_string()],
        "only the directory in the way"
    );
}
