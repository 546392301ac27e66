//! Assembling the single HTML page: template + style + embedded JSON + viewer script.
//!
//! The page is one file that needs no network: the viewer draws with its own WebGL code
//! (`web/*.js`), and its Content-Security-Policy ([`CONTENT_SECURITY_POLICY`]) lets the
//! browser load nothing from anywhere, so a page that tried would fail loudly, not quietly.

use pregrasp_geometry::ConvexHull;

use crate::data::ViewData;
use crate::options::ViewOptions;
use crate::Page;

/// The page's Content-Security-Policy: nothing is fetched (`default-src 'none'`), only the
/// page's own inline style and script run, and nothing may be framed or submitted.
pub const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'unsafe-inline'; \
     style-src 'unsafe-inline'; img-src data: blob:; base-uri 'none'; form-action 'none'";

const TEMPLATE: &str = include_str!("web/template.html");
const STYLE: &str = include_str!("web/viewer.css");
/// The viewer's script: its four files joined in order (each one's top-level names are seen by
/// the ones after it).
const SCRIPT: &str = concat!(
    include_str!("web/math.js"),
    "\n",
    include_str!("web/renderer.js"),
    "\n",
    include_str!("web/timeline.js"),
    "\n",
    include_str!("web/viewer.js"),
);

/// One self-contained HTML page showing `page`'s plan set with its part.
///
/// Every arm has a known model; the data's `known` flag stays for an arm the page cannot draw
/// (one from a robot description the caller could not load).
pub fn render_html(page: &Page<'_>, options: &ViewOptions) -> String {
    render_html_with_hull(page, None, options)
}

/// [`render_html`] with the part's convex hull given (object frame) when the caller has it —
/// the planner's, so that planning and drawing one plan compute one hull.
pub fn render_html_with_hull(
    page: &Page<'_>,
    hull: Option<&ConvexHull>,
    options: &ViewOptions,
) -> String {
    let data = ViewData::new(page, hull, options);
    let json = serde_json::to_string(&data).expect("view data serialises");
    fill_template(TEMPLATE, |key| match key {
        "TITLE" => Some(escape_html(&data.title)),
        "VERSION" => Some(env!("CARGO_PKG_VERSION").to_string()),
        "CSP" => Some(CONTENT_SECURITY_POLICY.to_string()),
        "STYLE" => Some(STYLE.to_string()),
        "DATA" => Some(escape_json_for_script(&json)),
        "SCRIPT" => Some(SCRIPT.to_string()),
        _ => None,
    })
}

/// Replaces every `{{KEY}}` of `template` in one pass (values are never re-scanned, so data
/// that happens to contain `{{…}}` stays as it is). Unknown keys are kept verbatim.
fn fill_template(template: &str, value: impl Fn(&str) -> Option<String>) -> String {
    let mut out = String::with_capacity(template.len());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        match after
            .find("}}")
            .and_then(|end| value(&after[..end]).map(|v| (end, v)))
        {
            Some((end, v)) => {
                out.push_str(&v);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// JSON text made safe inside a `<script>` element: `<`, `>`, `&` and the JavaScript line
/// separators U+2028/U+2029 become `\uXXXX` escapes. Those characters can only occur inside
/// JSON strings, where the escapes mean the same, so the text parses to the same value and
/// can contain neither `</script>` nor `<!--`.
pub fn escape_json_for_script(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    for c in json.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

/// Text made safe as HTML element content.
fn escape_html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn template_fill_is_single_pass() {
        let out = fill_template("a{{X}}b{{Y}}c{{Z", |k| match k {
            "X" => Some("{{Y}}".into()),
            "Y" => Some("y".into()),
            _ => None,
        });
        assert_eq!(out, "a{{Y}}byc{{Z");
    }

    #[test]
    fn script_escape_round_trips_and_hides_closing_tags() {
        let value = serde_json::json!({ "s": "</script><!-- a&b \u{2028} >" });
        let text = serde_json::to_string(&value).unwrap();
        let escaped = escape_json_for_script(&text);
        assert!(!escaped.contains('<') && !escaped.contains('>') && !escaped.contains('&'));
        assert!(!escaped.contains('\u{2028}'));
        let back: serde_json::Value = serde_json::from_str(&escaped).unwrap();
        assert_eq!(back, value);
    }

    #[test]
    fn html_escape() {
        assert_eq!(escape_html("a<b>&\"c"), "a&lt;b&gt;&amp;&quot;c");
    }

    #[test]
    fn the_policy_fetches_nothing() {
        let directives: Vec<&str> = CONTENT_SECURITY_POLICY.split(';').map(str::trim).collect();
        assert!(directives.contains(&"default-src 'none'"));
        // No directive allows a host, a scheme that reaches the network, or 'self'.
        for d in &directives {
            for word in d.split_whitespace().skip(1) {
                assert!(
                    ["'none'", "'unsafe-inline'", "data:", "blob:"].contains(&word),
                    "{d}"
                );
            }
        }
    }

    #[test]
    fn viewer_script_has_no_closing_script_tag() {
        assert!(!SCRIPT.to_ascii_lowercase().contains("</script"));
        assert!(!STYLE.to_ascii_lowercase().contains("</style"));
    }
}
