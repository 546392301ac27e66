//! Scene texts as the tests vary them.

/// The scene text with its `[grasps]` table replaced by `mode = "auto"` and `extra` lines.
pub fn auto_scene(text: &str, extra: &str) -> String {
    let start = text.find("[grasps]").expect("a [grasps] table");
    let end = text[start + 1..]
        .find("\n[")
        .map_or(text.len(), |k| start + 1 + k);
    format!(
        "{}[grasps]\nmode = \"auto\"\n{extra}{}",
        &text[..start],
        &text[end..]
    )
}
