//! The `[physics]` table of a scene file: read and range-checked by the scene loader, applied
//! on top of the defaults by the planner (`pregrasp_planner::hold::physics_settings`).

use std::path::Path;

use pregrasp_io::scene::{Scene, SceneError};
use pregrasp_model::PhysicsValue;
use pregrasp_physics::{PhysicsSettings, SettingsError};
use pregrasp_planner::hold::physics_settings;

/// The chair example's scene with `extra` appended.
fn chair_scene(extra: &str) -> Result<Scene, SceneError> {
    let example = pregrasp_examples::by_name("chair_side").unwrap();
    Scene::from_str(
        &format!("{}\n{extra}", example.scene_toml),
        Path::new("s.toml"),
    )
}

#[test]
fn physics_table_overrides_defaults() {
    let scene =
        chair_scene("[physics]\nmu_pad = 0.6\nmu_support = 0\nsafety_factor = 3\n").unwrap();
    let s = physics_settings(&scene.physics);
    assert_eq!((s.mu_pad, s.mu_support, s.safety_factor), (0.6, 0.0, 3.0));
    assert_eq!(s.density, PhysicsSettings::default().density);
    assert!(scene.physics.reject, "reject defaults to true");

    let none = chair_scene("").unwrap();
    assert_eq!(physics_settings(&none.physics), PhysicsSettings::default());
    assert!(none.physics.reject);
    assert!(
        !chair_scene("[physics]\nreject = false\n")
            .unwrap()
            .physics
            .reject
    );
}

#[test]
fn bad_physics_values_are_named() {
    let key = |t: &str| chair_scene(t).unwrap_err().key().map(str::to_string);
    assert_eq!(
        key("[physics]\nmu_pad = 0\n").as_deref(),
        Some("physics.mu_pad")
    );
    assert_eq!(
        key("[physics]\nmu_support = -0.1\n").as_deref(),
        Some("physics.mu_support")
    );
    assert_eq!(
        key("[physics]\nsafety_factor = 0.5\n").as_deref(),
        Some("physics.safety_factor")
    );
    assert_eq!(
        key("[physics]\ndensity = 1e9\n").as_deref(),
        Some("physics.density")
    );
    assert_eq!(
        key("[physics]\nsafety_factor = \"2\"\n").as_deref(),
        Some("physics.safety_factor")
    );
    assert_eq!(
        key("[physics]\nreject = 1\n").as_deref(),
        Some("physics.reject")
    );
    // A top-level key must come before the scene's tables.
    let example = pregrasp_examples::by_name("chair_side").unwrap();
    let top = Scene::from_str(
        &format!("physics = 3\n{}", example.scene_toml),
        Path::new("s.toml"),
    );
    assert_eq!(top.unwrap_err().key(), Some("physics"));
    // An unknown key is a warning, as everywhere in the scene format.
    let scene = chair_scene("[physics]\nfriction = 1\n").unwrap();
    assert!(scene
        .warnings
        .iter()
        .any(|w| w.contains("physics.friction")));
}

#[test]
fn command_line_values_are_range_checked() {
    let bad = PhysicsSettings {
        mu_pad: 0.0,
        ..PhysicsSettings::default()
    };
    let err = bad.validate().unwrap_err();
    assert!(matches!(
        err,
        SettingsError::Value {
            key: PhysicsValue::MuPad,
            ..
        }
    ));
    assert_eq!(err.to_string(), "mu_pad: must be in (0, 10], found 0");
    assert!(PhysicsSettings::default().validate().is_ok());
}
