//! Collision geometry from the shipped URDFs' meshes: containment of every mesh vertex, the
//! cache (round trip, corrupt entries), the missing-mesh error, and self-collision of the
//! FR3 at its ready pose and folded into itself.

mod common;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
use std::sync::OnceLock;

use common::{data, model};
use nalgebra::{Isometry3, Translation3};
use pregrasp_urdf::geometry::load::{collision_elements, element_mesh};
use pregrasp_urdf::geometry::pieces::max_outside;
use pregrasp_urdf::geometry::LinkTree;
use pregrasp_urdf::{
    origin_isometry, CacheDir, CacheOutcome, GeometryOptions, UrdfError, UrdfGeometry, UrdfModel,
};

fn no_cache() -> GeometryOptions {
    GeometryOptions {
        cache: CacheDir::Off,
        ..Default::default()
    }
}

fn geometry(name: &'static str) -> &'static UrdfGeometry {
    static FR3: OnceLock<UrdfGeometry> = OnceLock::new();
    static XARM6: OnceLock<UrdfGeometry> = OnceLock::new();
    let cell = if name == "fr3.urdf" { &FR3 } else { &XARM6 };
    cell.get_or_init(|| UrdfGeometry::compute(&model(name), &no_cache()).unwrap())
}

/// Every vertex of every collision mesh lies inside its element's piece (1e-9 m), every
/// link with `<collision>` elements has one piece per element, and the boxes' pieces are
/// their corners.
fn check_containment(name: &'static str, links: &[&str]) {
    let m = model(name);
    let g = geometry(name);
    let got: Vec<&str> = g.links.iter().map(|l| l.link.as_str()).collect();
    assert_eq!(got, links);
    let elements = collision_elements(&m, &no_cache()).unwrap();
    assert_eq!(
        elements.len(),
        g.links.iter().map(|l| l.pieces.len()).sum::<usize>()
    );
    for e in &elements {
        let l = &g.links[g.index_of(&e.link).unwrap()];
        let k = l.elements.iter().position(|&i| i == e.index).unwrap();
        let piece = &l.pieces[k];
        match element_mesh(&m, e).unwrap() {
            Some(mesh) => {
                let out = max_outside(piece, &mesh.vertices);
                assert!(out <= 1e-9, "{name} {}: a vertex {out} m outside", e.link);
                assert!(piece.len() < mesh.vertices.len());
            }
            None => assert_eq!(piece.len(), 8, "{name} {}: a box is its 8 corners", e.link),
        }
    }
}

#[test]
fn fr3_mesh_vertices_lie_inside_their_pieces() {
    let mut links: Vec<String> = (0..8).map(|i| format!("fr3_link{i}")).collect();
    links.extend(["fr3_hand", "fr3_leftfinger", "fr3_rightfinger"].map(String::from));
    check_containment(
        "fr3.urdf",
        &links.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    let g = geometry("fr3.urdf");
    // The fingers are 4 boxes each.
    assert_eq!(
        g.links[g.index_of("fr3_leftfinger").unwrap()].pieces.len(),
        4
    );
}

#[test]
fn xarm6_mesh_vertices_lie_inside_their_pieces() {
    let links = [
        "link_base",
        "link1",
        "link2",
        "link3",
        "link4",
        "link5",
        "link6",
    ];
    check_containment("xarm6.urdf", &links);
}

#[test]
fn cache_round_trip_and_corrupt_entries() {
    let tmp = tempfile::tempdir().unwrap();
    let opts = GeometryOptions {
        cache: CacheDir::At(tmp.path().to_path_buf()),
        ..Default::default()
    };
    let m = model("fr3.urdf");
    let first = UrdfGeometry::load(&m, &opts).unwrap();
    let CacheOutcome::Written(path) = first.cache.clone() else {
        panic!("{:?}", first.cache)
    };
    assert!(path.starts_with(tmp.path()) && path.is_file());
    let again = UrdfGeometry::load(&m, &opts).unwrap();
    assert_eq!(again.cache, CacheOutcome::Hit(path.clone()));
    // Bit-identical pieces and pairs, and the same as without the cache.
    assert_eq!(again.geometry, first.geometry);
    assert_eq!(&first.geometry, geometry("fr3.urdf"));
    // A corrupt entry (garbage, truncated, another key) is recomputed, never an error.
    let text = std::fs::read(&path).unwrap();
    let other_key =
        String::from_utf8(text.clone())
            .unwrap()
            .replacen(&first.geometry.key, &"0".repeat(32), 2);
    for bad in [
        b"\x00garbage".to_vec(),
        text[..text.len() / 2].to_vec(),
        other_key.into_bytes(),
    ] {
        std::fs::write(&path, bad).unwrap();
        let fixed = UrdfGeometry::load(&m, &opts).unwrap();
        assert!(
            matches!(fixed.cache, CacheOutcome::Replaced(ref p, _) if *p == path),
            "{:?}",
            fixed.cache
        );
        assert_eq!(fixed.geometry, first.geometry);
        assert_eq!(
            UrdfGeometry::load(&m, &opts).unwrap().cache,
            CacheOutcome::Hit(path.clone())
        );
    }
    // No temporary files left behind.
    assert_eq!(
        std::fs::read_dir(path.parent().unwrap()).unwrap().count(),
        1
    );
    // A cache folder that cannot be created: computed, not cached, no error.
    let blocked = tmp.path().join("a-file");
    std::fs::write(&blocked, b"").unwrap();
    let opts = GeometryOptions {
        cache: CacheDir::At(blocked),
        ..Default::default()
    };
    let loaded = UrdfGeometry::load(&m, &opts).unwrap();
    assert!(matches!(loaded.cache, CacheOutcome::NotCached(_)));
    assert_eq!(loaded.geometry, first.geometry);
}

#[test]
fn the_key_follows_the_mesh_bytes() {
    // The same URDF next to a copy of its meshes with one byte changed: another key.
    let tmp = tempfile::tempdir().unwrap();
    let urdf = tmp.path().join("fr3.urdf");
    std::fs::copy(data("fr3.urdf"), &urdf).unwrap();
    let copy = |dir: &std::path::Path| {
        for f in [
            "link0", "link1", "link2", "link3", "link4", "link5", "link6", "link7",
        ] {
            let rel = format!("franka_description/meshes/robot_arms/fr3/collision/{f}.stl");
            std::fs::create_dir_all(dir.join(&rel).parent().unwrap()).unwrap();
            std::fs::copy(data(&format!("meshes/{rel}")), dir.join(&rel)).unwrap();
        }
        let rel = "franka_description/meshes/robot_ee/franka_hand_white/collision/hand.stl";
        std::fs::create_dir_all(dir.join(rel).parent().unwrap()).unwrap();
        std::fs::copy(data(&format!("meshes/{rel}")), dir.join(rel)).unwrap();
    };
    copy(&tmp.path().join("meshes"));
    let m = UrdfModel::from_file(&urdf).unwrap();
    let opts = GeometryOptions {
        cache: CacheDir::At(tmp.path().join("cache")),
        ..Default::default()
    };
    let a = UrdfGeometry::load(&m, &opts).unwrap().geometry;
    assert_eq!(
        a.key,
        geometry("fr3.urdf").key,
        "paths are not part of the key"
    );
    let hand = tmp
        .path()
        .join("meshes/franka_description/meshes/robot_ee/franka_hand_white/collision/hand.stl");
    let mut bytes = std::fs::read(&hand).unwrap();
    bytes[0] ^= 1; // the STL header: same triangles, other bytes
    std::fs::write(&hand, bytes).unwrap();
    let b = UrdfGeometry::load(&m, &opts).unwrap();
    assert!(matches!(b.cache, CacheOutcome::Written(_)));
    assert_ne!(b.geometry.key, a.key);
    assert_eq!(b.geometry.links, a.links);
}

#[test]
fn a_missing_mesh_names_the_urdf_the_link_the_file_and_the_search_path() {
    let tmp = tempfile::tempdir().unwrap();
    let urdf = tmp.path().join("fr3.urdf");
    std::fs::copy(data("fr3.urdf"), &urdf).unwrap();
    let m = UrdfModel::from_file(&urdf).unwrap();
    let extra = tmp.path().join("my-meshes");
    let opts = GeometryOptions {
        mesh_dirs: vec![extra.clone()],
        ..no_cache()
    };
    let err = UrdfGeometry::load(&m, &opts).unwrap_err();
    let UrdfError::MissingMesh {
        ref file,
        ref link,
        ref filename,
        ref searched,
    } = err
    else {
        panic!("{err}")
    };
    assert_eq!(file, &urdf.display().to_string());
    assert_eq!(link, "fr3_link0");
    assert_eq!(
        filename,
        "package://franka_description/meshes/robot_arms/fr3/collision/link0.stl"
    );
    let expected = [extra, tmp.path().to_path_buf(), tmp.path().join("meshes")];
    assert_eq!(
        searched,
        &expected.map(|d| d.display().to_string()).to_vec()
    );
    let text = err.to_string();
    for part in [
        urdf.display().to_string(),
        "fr3_link0".into(),
        filename.clone(),
        searched[0].clone(),
    ] {
        assert!(text.contains(&part), "{text} lacks {part}");
    }
}

/// The pose of every link of the FR3 at arm joints `q` and finger opening `finger`: the
/// arm links from `SerialChain::link_frames`, each finger from the hand frame through its
/// prismatic joint (`origin · Trans(axis · d)`).
fn fr3_poses(q: &[f64; 7], finger: f64) -> impl Fn(&str) -> Option<Isometry3<f64>> {
    let m = model("fr3.urdf");
    let chain = m.chain("fr3_link0", "fr3_hand_tcp").unwrap();
    let frames = chain.link_frames(q);
    let mut poses: Vec<(String, Isometry3<f64>)> = chain
        .links()
        .iter()
        .map(|l| l.name.clone())
        .zip(frames)
        .collect();
    let hand = poses.iter().find(|(n, _)| n == "fr3_hand").unwrap().1;
    for (joint, link) in [
        ("fr3_finger_joint1", "fr3_leftfinger"),
        ("fr3_finger_joint2", "fr3_rightfinger"),
    ] {
        let j = m.joint(joint).unwrap();
        let axis = nalgebra::Vector3::from(j.axis.xyz.0);
        let slide = Isometry3::from_parts(Translation3::from(axis * finger), Default::default());
        poses.push((link.to_string(), hand * origin_isometry(&j.origin) * slide));
    }
    move |name| poses.iter().find(|(n, _)| n == name).map(|p| p.1)
}

#[test]
fn fr3_ready_pose_is_free_and_a_folded_pose_collides() {
    let g = geometry("fr3.urdf");
    let ready = [
        0.0,
        -FRAC_PI_4,
        0.0,
        -3.0 * FRAC_PI_4,
        0.0,
        FRAC_PI_2,
        FRAC_PI_4,
    ];
    assert_eq!(g.colliding_pairs(fr3_poses(&ready, 0.04)), vec![]);
    // Elbow folded to its limit, shoulder forward: the hand comes down onto link1/link2.
    let folded = [0.0, 0.5, 0.0, -3.0, 0.0, 0.6, 0.0];
    let limits = model("fr3.urdf")
        .chain("fr3_link0", "fr3_link8")
        .unwrap()
        .limits();
    assert!(folded.iter().zip(&limits).all(|(q, l)| l.contains(*q)));
    let hits: Vec<(&str, &str)> = g
        .colliding_pairs(fr3_poses(&folded, 0.04))
        .into_iter()
        .map(|p| g.pair_names(p))
        .collect();
    assert!(hits.contains(&("fr3_link1", "fr3_hand")), "{hits:?}");
    assert!(hits.contains(&("fr3_link2", "fr3_hand")), "{hits:?}");
}

#[test]
fn pairs_exclude_adjacent_links_and_allowed_lists_remove_more() {
    let mut g = geometry("fr3.urdf").clone();
    let pair = |g: &UrdfGeometry, a: &str, b: &str| {
        let (i, j) = (g.index_of(a).unwrap(), g.index_of(b).unwrap());
        (i.min(j), i.max(j))
    };
    let why = |g: &UrdfGeometry, a, b| {
        let p = pair(g, a, b);
        g.excluded_pairs
            .iter()
            .find(|e| (e.a, e.b) == p)
            .map(|e| e.why)
    };
    use pregrasp_urdf::geometry::Exclusion::*;
    assert_eq!(why(&g, "fr3_link3", "fr3_link4"), Some(Adjacent));
    // link7, link8 and the hand are one body (fixed joints): the hand is adjacent to link6.
    assert_eq!(why(&g, "fr3_link6", "fr3_hand"), Some(Adjacent));
    assert_eq!(why(&g, "fr3_link7", "fr3_leftfinger"), Some(Adjacent));
    assert_eq!(why(&g, "fr3_link0", "fr3_link2"), Some(Never));
    // Every pair is either checked or excluded, once.
    let n = g.links.len();
    assert_eq!(
        g.self_collision_pairs.len() + g.excluded_pairs.len(),
        n * (n - 1) / 2
    );
    let checked = pair(&g, "fr3_link1", "fr3_hand");
    assert!(g.self_collision_pairs.contains(&checked));
    assert!(g.allow("fr3_hand", "fr3_link1").unwrap());
    assert!(!g.self_collision_pairs.contains(&checked));
    assert_eq!(why(&g, "fr3_link1", "fr3_hand"), Some(Allowed));
    assert!(!g.allow("fr3_link1", "fr3_hand").unwrap());
    assert!(matches!(
        g.allow("fr3_link1", "fr3_link8"),
        Err(UrdfError::UnknownLink { .. })
    ));
    // Deterministic: the same seed gives the same pairs.
    let again = UrdfGeometry::compute(&model("fr3.urdf"), &no_cache()).unwrap();
    assert_eq!(&again, geometry("fr3.urdf"));
}

#[test]
fn tree_poses_agree_with_the_serial_chain() {
    let m = model("fr3.urdf");
    let tree = LinkTree::new(&m).unwrap();
    let chain = m.chain("fr3_link0", "fr3_hand_tcp").unwrap();
    let q = [0.3, -0.5, 0.2, -2.0, 0.4, 1.8, -0.6];
    let mut tq = q.to_vec();
    tq.push(0.02); // fr3_finger_joint1
    let poses = tree.poses(&tq);
    for (l, f) in chain.links().iter().zip(chain.link_frames(&q)) {
        let i = tree.link_names().iter().position(|n| *n == l.name).unwrap();
        assert!(
            (poses[i].to_homogeneous() - f.to_homogeneous()).norm() < 1e-12,
            "{}",
            l.name
        );
    }
    let finger = fr3_poses(&q, 0.02);
    for name in ["fr3_leftfinger", "fr3_rightfinger"] {
        let i = tree.link_names().iter().position(|n| n == name).unwrap();
        let d = poses[i].to_homogeneous() - finger(name).unwrap().to_homogeneous();
        assert!(d.norm() < 1e-12, "{name}");
    }
}
