//! The page embeds valid JSON that round-trips the plan, needs no network (no URL, no
//! import, a policy that forbids fetching), escapes script-closing text, and carries correct
//! robot models and hull edges.

use pregrasp_io::plan_file::GraspKind;
use pregrasp_io::plan_file::PlanFile;
use pregrasp_robot::{UrKinematics, UrModel};
use pregrasp_viewer::{ViewOptions, CONTENT_SECURITY_POLICY};

mod common;

use common::{fixture, render as render_html};
use serde_json::Value;

const DATA_OPEN: &str = r#"<script type="application/json" id="pregrasp-data">"#;

/// The text of the embedded data script, parsed.
fn embedded(html: &str) -> Value {
    let start = html.find(DATA_OPEN).expect("data script present") + DATA_OPEN.len();
    let end = start + html[start..].find("</script>").expect("data script closed");
    serde_json::from_str(&html[start..end]).expect("embedded data is valid JSON")
}

fn demo() -> (PlanFile, String) {
    let plan = fixture::demo_plan("plate.stl").expect("fixture builds");
    let html = render_html(&plan, &fixture::plate_mesh(), &ViewOptions::default());
    (plan, html)
}

#[test]
fn embedded_plan_round_trips() {
    let (plan, html) = demo();
    let data = embedded(&html);
    assert_eq!(data["format"], "pregrasp.view/1");
    let back: PlanFile = serde_json::from_value(data["plan"].clone()).unwrap();
    assert_eq!(back, plan);
    assert_eq!(data["plan"], serde_json::to_value(&plan).unwrap());
}

/// The page is one file: it names no URL, loads no script, style or module from anywhere, and
/// its Content-Security-Policy (the first thing in `<head>`, before any script) forbids
/// fetching, so the browser itself refuses any request the page might make.
#[test]
fn the_page_needs_no_network() {
    let (_, html) = demo();
    let lower = html.to_ascii_lowercase();
    for needle in [
        "http:",
        "https:",
        "//cdn",
        "<script src",
        " src=",
        "<link",
        "@import",
        "importmap",
        "import(",
        "from '",
        "from \"",
        "fetch(",
        "xmlhttprequest",
        "websocket",
        "eventsource",
        "sendbeacon",
    ] {
        assert!(!lower.contains(needle), "the page contains {needle:?}");
    }
    let csp = format!(
        r#"<meta http-equiv="Content-Security-Policy" content="{CONTENT_SECURITY_POLICY}">"#
    );
    let csp_at = html.find(&csp).expect("the policy is in the page");
    assert!(csp_at < html.find("<script").unwrap());
    assert!(csp_at < html.find("<style").unwrap());
    // Exactly two scripts: the data and the viewer, both inline.
    assert_eq!(lower.matches("<script type=").count(), 2);
    assert_eq!(lower.matches("</script>").count(), 2);
    assert!(html.contains(r#"<script type="module">"#));
}

/// The viewer draws every shape kind the data may carry, and every gripper set.
#[test]
fn the_script_draws_every_shape_kind_and_gripper_set() {
    let (_, html) = demo();
    for needle in [
        "'capsule'",
        "'cylinder'",
        "'cuboid'",
        "closed_precision",
        "closed_power",
        "getContext('webgl'",
    ] {
        assert!(html.contains(needle), "the viewer script lacks {needle}");
    }
}

#[test]
fn script_closing_text_in_the_data_is_escaped() {
    let mut plan = fixture::no_plan("a</script><script>alert(1)</script>.stl");
    plan.reason = Some("</SCRIPT> <!-- & \u{2028}".into());
    plan.scene.name = Some("<b>x</b>".into());
    let html = render_html(&plan, &fixture::plate_mesh(), &ViewOptions::default());
    // Exactly the page's own two scripts are closed; nothing from the data.
    assert_eq!(html.to_ascii_lowercase().matches("</script").count(), 2);
    assert!(!html.contains("<b>x</b>"), "the title is HTML-escaped");
    assert!(html.contains("<title>&lt;b&gt;x&lt;/b&gt;</title>"));
    let back: PlanFile = serde_json::from_value(embedded(&html)["plan"].clone()).unwrap();
    assert_eq!(back, plan);
}

#[test]
fn mesh_and_hull_edges_match_the_part() {
    let (_, html) = demo();
    let data = embedded(&html);
    let mesh = fixture::plate_mesh();
    let positions: Vec<f64> = data["mesh"]["positions"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(positions.len(), 3 * mesh.vertices.len());
    for (p, v) in positions.chunks(3).zip(&mesh.vertices) {
        assert!(
            (p[0] - v.x).abs() < 1e-6 && (p[1] - v.y).abs() < 1e-6 && (p[2] - v.z).abs() < 1e-6
        );
    }
    let indices: Vec<u64> = data["mesh"]["indices"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let expected: Vec<u64> = mesh.triangles.iter().flatten().map(|&i| i as u64).collect();
    assert_eq!(indices, expected);
    // A box has exactly 12 feature edges, each parallel to one axis (no face diagonals).
    let edges = data["hull_edges"].as_array().unwrap();
    assert_eq!(edges.len(), 12);
    for e in edges {
        let e: Vec<f64> = e
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let moved = (0..3).filter(|&k| (e[k] - e[k + 3]).abs() > 1e-6).count();
        assert_eq!(moved, 1, "edge {e:?} is not axis-parallel");
    }
}

#[test]
fn robot_models_carry_dh_shapes_and_a_correct_fk_check() {
    let (plan, html) = demo();
    let data = embedded(&html);
    let robots = data["robots"].as_array().unwrap();
    assert_eq!(robots.len(), plan.robots.len());
    let kin = UrKinematics::new(UrModel::Ur5e);
    let dh = UrModel::Ur5e.dh();
    for r in robots {
        assert_eq!(r["known"], true);
        for i in 0..6 {
            let (d, a, alpha) = dh.row(i);
            assert_eq!(r["dh"]["d"][i].as_f64().unwrap(), d);
            assert_eq!(r["dh"]["a"][i].as_f64().unwrap(), a);
            assert_eq!(r["dh"]["alpha"][i].as_f64().unwrap(), alpha);
        }
        assert_eq!(
            r["links"].as_array().unwrap().len(),
            pregrasp_robot::arm_geometry(UrModel::Ur5e).links.len()
        );
        for shape in r["links"]
            .as_array()
            .unwrap()
            .iter()
            .chain(r["gripper"]["open"].as_array().unwrap())
        {
            let kind = shape["kind"].as_str().unwrap();
            assert!(["capsule", "cylinder", "cuboid"].contains(&kind), "{kind}");
            assert!(shape["frame"].as_u64().unwrap() <= 6);
        }
        let checks = r["fk_check"].as_array().unwrap();
        assert!(checks.len() >= 2);
        for c in checks {
            let q: [f64; 6] = serde_json::from_value(c["q"].clone()).unwrap();
            let pose: pregrasp_io::plan_file::PoseJson =
                serde_json::from_value(c["flange"].clone()).unwrap();
            let want = kin.fk(&q);
            assert!(
                (pose.to_isometry().translation.vector - want.translation.vector).norm() < 1e-12
            );
        }
    }
}

#[test]
fn options_and_title_reach_the_page() {
    let plan = fixture::no_plan("plate.stl");
    let options = ViewOptions {
        title: Some("my view".into()),
        initial_plan: 1,
        speed: 2.0,
        autoplay: false,
    };
    let html = render_html(&plan, &fixture::plate_mesh(), &options);
    let data = embedded(&html);
    assert_eq!(data["title"], "my view");
    assert_eq!(data["options"]["initial_plan"], 1);
    assert_eq!(data["options"]["speed"], 2.0);
    assert_eq!(data["options"]["autoplay"], false);
    assert!(html.contains("<title>my view</title>"));
    // Default title: the scene name.
    let html = render_html(&plan, &fixture::plate_mesh(), &ViewOptions::default());
    assert_eq!(embedded(&html)["title"], "viewer fixture: plate");
}

#[test]
fn a_degenerate_mesh_still_renders_without_hull_edges() {
    let plan = fixture::no_plan("plate.stl");
    let mesh = pregrasp_geometry::Mesh {
        vertices: vec![],
        triangles: vec![],
    };
    let html = render_html(&plan, &mesh, &ViewOptions::default());
    assert_eq!(embedded(&html)["hull_edges"].as_array().unwrap().len(), 0);
}

/// A gripper holding the part is drawn closed at the width the plan records: the pads of the
/// `closed_precision` / `closed_power` sets face each other `grip_width` apart.
#[test]
fn holding_grippers_are_drawn_at_their_grip_width() {
    let mut plan = fixture::demo_plan("plate.stl").expect("fixture builds");
    for seg in plan.plans.iter_mut().flat_map(|p| p.segments.iter_mut()) {
        seg.grip_width = Some(if seg.grasp == GraspKind::Support {
            0.030
        } else {
            0.050
        });
    }
    let html = render_html(&plan, &fixture::plate_mesh(), &ViewOptions::default());
    let data = embedded(&html);
    for r in data["robots"].as_array().unwrap() {
        for (set, width) in [("closed_precision", 0.030), ("closed_power", 0.050)] {
            let Some(shapes) = r["gripper"][set].as_array() else {
                continue;
            };
            // Inner face of each pad box: |centre x| − its half extent along x (the pads are
            // not rotated about y).
            let faces: Vec<f64> = shapes
                .iter()
                .filter(|s| s["name"].as_str().unwrap().starts_with("gripper_pad_"))
                .map(|s| {
                    let x = s["pose"]["xyz"][0].as_f64().unwrap();
                    x.abs() - s["half_extents"][0].as_f64().unwrap()
                })
                .collect();
            assert_eq!(faces.len(), 2, "{set}: two pads");
            for f in faces {
                assert!((f - width / 2.0).abs() < 2e-4, "{set}: pad face at {f}");
            }
        }
        assert!(
            r["gripper"]["closed_precision"].is_array() || r["gripper"]["closed_power"].is_array()
        );
    }
}

/// The page embeds the plan file's JSON text as the caller gives it, byte for byte, and takes
/// its title from the caller when the options give none.
#[test]
fn the_callers_plan_text_and_title_are_embedded_verbatim() {
    let plan = fixture::demo_plan("plate.stl").expect("fixture builds");
    let text = plan.to_json();
    let json = serde_json::value::RawValue::from_string(text.trim_end().to_string()).unwrap();
    let mut set = plan.to_model().unwrap();
    // What the Rust side draws comes from the set, not from the embedded text.
    for seg in set.plans.iter_mut().flat_map(|p| p.segments.iter_mut()) {
        seg.closing.width = Some(0.03);
    }
    let mesh = fixture::plate_mesh();
    let page = pregrasp_viewer::Page {
        set: &set,
        plan_json: &json,
        title: "from the caller",
        mesh: &mesh,
        arms: None,
        grippers: None,
    };
    let html = pregrasp_viewer::render_html(&page, &ViewOptions::default());
    let escaped = pregrasp_viewer::escape_json_for_script(text.trim_end());
    assert!(html.contains(&format!(r#""plan":{escaped},"mesh":"#)));
    assert_eq!(embedded(&html)["title"], "from the caller");
    // Built-in arms are drawn without descriptions; the grippers fall back to the 2F-85,
    // closed where the set's segments say.
    for r in embedded(&html)["robots"].as_array().unwrap() {
        assert_eq!(r["known"], true);
        assert!(r["gripper"]["closed_power"].is_array());
    }
}
