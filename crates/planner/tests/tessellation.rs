//! The plan belongs to the part, not to how its surface is cut into triangles: each example's
//! mesh with every triangle split into 16 (two rounds of midpoint subdivision, the same surface)
//! plans as the mesh itself does — the same candidates, outcomes and θ_goal, the same plans to
//! 1e-9 (measured: only the grip check's numbers differ, at 1e-14, through the mass from the
//! mesh's volume). CAD exports of real parts cut flat faces into many small triangles; the
//! closing, the checks and the grip check must not see a different part there.

use std::collections::HashMap;
use std::path::Path;

use pregrasp_geometry::{Mesh, Point};
use pregrasp_io::plan_file::PlanFile;
use pregrasp_io::scene::Scene;
use pregrasp_planner::pipeline::{plan, PlanOptions};
use serde_json::Value;

/// One round of midpoint subdivision: every triangle into four, the midpoints of shared edges
/// shared (a closed mesh stays closed).
fn subdivide(mesh: &Mesh) -> Mesh {
    let mut vertices = mesh.vertices.clone();
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<Point>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let m = nalgebra::center(&vertices[a as usize], &vertices[b as usize]);
            vertices.push(m);
            (vertices.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(4 * mesh.triangles.len());
    for &[a, b, c] in &mesh.triangles {
        let ab = midpoint(a, b, &mut vertices);
        let bc = midpoint(b, c, &mut vertices);
        let ca = midpoint(c, a, &mut vertices);
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh::new(vertices, triangles)
}

fn planned(name: &str, mesh: &Mesh) -> Value {
    let ex = pregrasp_examples::by_name(name).expect("built-in example");
    let scene = Scene::from_str(&ex.scene_toml, Path::new(&format!("examples/{name}.toml")))
        .expect("scene parses");
    let file: PlanFile = plan(&scene, mesh, &PlanOptions::default(), &|_| {}, &|| {})
        .unwrap()
        .file;
    let mut json = serde_json::to_value(&file).unwrap();
    json.as_object_mut().unwrap().remove("timing_ms");
    json
}

/// Every difference between `a` and `b` beyond `tol` (relative to the larger number, at least
/// absolute), as paths; strings, booleans and shapes must be equal.
fn differences(a: &Value, b: &Value, path: &str, tol: f64, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            if (x - y).abs() > tol * x.abs().max(y.abs()).max(1.0) {
                out.push(format!("{path}: {x} vs {y}"));
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (k, (p, q)) in x.iter().zip(y).enumerate() {
                differences(p, q, &format!("{path}/{k}"), tol, out);
            }
        }
        (Value::Object(x), Value::Object(y)) if x.len() == y.len() => {
            for (k, p) in x {
                match y.get(k) {
                    Some(q) => differences(p, q, &format!("{path}/{k}"), tol, out),
                    None => out.push(format!("{path}/{k}: missing")),
                }
            }
        }
        _ if a == b => {}
        _ => out.push(format!("{path}: {a} vs {b}")),
    }
}

#[test]
fn a_finer_tessellation_of_the_same_part_plans_the_same() {
    for name in pregrasp_examples::NAMES {
        let mesh = pregrasp_examples::by_name(name).unwrap().mesh;
        let fine = subdivide(&subdivide(&mesh));
        assert_eq!(fine.triangles.len(), 16 * mesh.triangles.len());
        let (coarse, fine) = (planned(name, &mesh), planned(name, &fine));
        assert_eq!(coarse["status"], "planned", "{name}");
        let mut diffs = Vec::new();
        differences(&coarse, &fine, "", 1e-9, &mut diffs);
        assert!(
            diffs.is_empty(),
            "{name}: {} numbers differ, e.g. {:?}",
            diffs.len(),
            &diffs[..diffs.len().min(8)]
        );
    }
}
