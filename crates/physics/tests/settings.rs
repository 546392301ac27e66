//! The `[physics]` table of a scene file.

use pregrasp_physics::{PhysicsSettings, SettingsError};

#[test]
fn physics_table_overrides_defaults() {
    let text = "name = \"x\"\n[object]\nmesh = \"a.stl\"\n[physics]\nmu_pad = 0.6\nmu_support = 0\nsafety_factor = 3\n";
    let s = PhysicsSettings::default()
        .with_scene_toml(text, "s.toml")
        .unwrap();
    assert_eq!((s.mu_pad, s.mu_support, s.safety_factor), (0.6, 0.0, 3.0));
    let none = PhysicsSettings::default()
        .with_scene_toml("[object]\n", "s.toml")
        .unwrap();
    assert_eq!(none, PhysicsSettings::default());
}

#[test]
fn bad_physics_values_are_named() {
    let err = |t: &str| {
        PhysicsSettings::default()
            .with_scene_toml(t, "s.toml")
            .unwrap_err()
    };
    assert!(
        matches!(err("[physics]\nmu_pad = 0\n"), SettingsError::Value { key, .. } if key == "physics.mu_pad")
    );
    assert!(
        matches!(err("[physics]\nfriction = 1\n"), SettingsError::Value { key, .. } if key == "physics.friction")
    );
    assert!(matches!(
        err("[physics]\nsafety_factor = \"2\"\n"),
        SettingsError::Value { .. }
    ));
    assert!(matches!(err("physics = 3\n"), SettingsError::Value { .. }));
    assert!(matches!(err("[physics\n"), SettingsError::Parse { .. }));
}
