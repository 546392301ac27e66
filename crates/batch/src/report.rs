//! The batch's summary: `summary.csv` (one row per scene), `summary.json` (counts and rows)
//! and `report.html` (counts by outcome, a table that sorts by any column, each scene linked to
//! its viewer page). Written together, all or none.

use std::fmt::Write as _;
use std::path::Path;

use pregrasp_io::output::{OutputError, OutputId, Outputs};

use crate::{Record, SceneStatus};

/// Scenes per outcome: planned, no plan, error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Counts {
    pub scenes: usize,
    pub planned: usize,
    pub no_plan: usize,
    pub error: usize,
    /// Plans reused because their scene and mesh had not changed.
    pub reused: usize,
}

impl Counts {
    pub fn of(records: &[Record]) -> Counts {
        let mut c = Counts {
            scenes: records.len(),
            ..Counts::default()
        };
        for r in records {
            match r.status {
                SceneStatus::Planned => c.planned += 1,
                SceneStatus::NoPlan => c.no_plan += 1,
                SceneStatus::Error => c.error += 1,
            }
            c.reused += usize::from(r.reused);
        }
        c
    }
}

#[derive(serde::Serialize)]
struct Summary<'a> {
    counts: Counts,
    scenes: &'a [Record],
}

/// The CSV text: a header and one row per record.
pub fn csv(records: &[Record]) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in records {
        w.serialize(r)?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8(bytes).expect("CSV of UTF-8 fields"))
}

/// The JSON text: counts and every record.
pub fn json(records: &[Record]) -> String {
    let mut s = serde_json::to_string_pretty(&Summary {
        counts: Counts::of(records),
        scenes: records,
    })
    .expect("records serialise");
    s.push('\n');
    s
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The HTML report (self-contained: inline style and script, no network).
pub fn html(records: &[Record], title: &str) -> String {
    let c = Counts::of(records);
    let num = |v: Option<f64>, d: usize| v.map_or(String::new(), |x| format!("{x:.d$}"));
    let mut rows = String::new();
    for r in records {
        let scene = match &r.view_file {
            Some(v) => format!("<a href=\"{}\">{}</a>", esc(v), esc(&r.scene)),
            None => esc(&r.scene),
        };
        let _ = writeln!(
            rows,
            "<tr class=\"{st}\"><td>{scene}</td><td>{st}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.0}</td><td>{}</td><td class=\"reason\">{}</td></tr>",
            num(r.best_score, 3),
            num(r.theta_goal_deg, 1),
            r.plans,
            num(r.grip_force, 0),
            esc(&r.check),
            r.time_ms,
            if r.reused { "yes" } else { "" },
            esc(r.reason.as_deref().unwrap_or("")),
            st = r.status,
        );
    }
    format!(
        r#"<!doctype html>
<html lang="en"><head><meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src 'unsafe-inline'; script-src 'unsafe-inline'">
<title>{title}</title>
<style>
body {{ font: 14px system-ui, sans-serif; margin: 24px; color: #222; }}
.counts span {{ display: inline-block; margin-right: 18px; padding: 6px 12px; border-radius: 6px; background: #eee; }}
.counts .planned {{ background: #d8f0d8; }} .counts .no_plan {{ background: #f6ecc8; }} .counts .error {{ background: #f4d0d0; }}
table {{ border-collapse: collapse; margin-top: 16px; width: 100%; }}
th, td {{ border-bottom: 1px solid #ddd; padding: 4px 8px; text-align: left; vertical-align: top; }}
th {{ cursor: pointer; background: #f4f4f4; user-select: none; }}
th.sorted::after {{ content: " ▲"; }} th.sorted.desc::after {{ content: " ▼"; }}
tr.no_plan td:nth-child(2) {{ color: #8a6d00; }} tr.error td:nth-child(2) {{ color: #b00020; }}
td.reason {{ max-width: 520px; font-size: 12px; color: #555; }}
</style></head><body>
<h1>{title}</h1>
<p class="counts"><span>{scenes} scenes</span><span class="planned">{planned} planned</span><span class="no_plan">{no_plan} no plan</span><span class="error">{error} errors</span><span>{reused} reused (up to date)</span></p>
<table id="t"><thead><tr><th>scene</th><th>status</th><th>score</th><th>θ_goal °</th><th>plans</th><th>grip N</th><th>check</th><th>ms</th><th>reused</th><th>reason</th></tr></thead>
<tbody>
{rows}</tbody></table>
<script>
(() => {{
  const t = document.getElementById("t");
  t.querySelectorAll("th").forEach((th, col) => th.addEventListener("click", () => {{
    const desc = th.classList.contains("sorted") && !th.classList.contains("desc");
    t.querySelectorAll("th").forEach(h => h.classList.remove("sorted", "desc"));
    th.classList.add("sorted"); if (desc) th.classList.add("desc");
    const rows = [...t.tBodies[0].rows];
    const key = r => r.cells[col].textContent;
    rows.sort((a, b) => {{
      const x = key(a), y = key(b), nx = parseFloat(x), ny = parseFloat(y);
      const c = (!isNaN(nx) && !isNaN(ny)) ? nx - ny : x.localeCompare(y);
      return desc ? -c : c;
    }});
    rows.forEach(r => t.tBodies[0].appendChild(r));
  }}));
}})();
</script>
</body></html>
"#,
        title = esc(title),
        scenes = c.scenes,
        planned = c.planned,
        no_plan = c.no_plan,
        error = c.error,
        reused = c.reused,
    )
}

/// Declares the summary files under `out` in `outputs` (before any planning, so a folder in
/// the way is found at once); [`stage`] fills them.
pub fn declare(outputs: &mut Outputs, out: &Path) -> Result<[OutputId; 3], OutputError> {
    let [csv, json, html] = crate::SUMMARY_FILES.map(|f| out.join(f));
    Ok([
        outputs.declare_creating_dirs(&csv)?,
        outputs.declare_creating_dirs(&json)?,
        outputs.declare_creating_dirs(&html)?,
    ])
}

/// Stages `summary.csv`, `summary.json` and `report.html` into the outputs [`declare`] made.
pub fn stage(
    outputs: &mut Outputs,
    ids: [OutputId; 3],
    records: &[Record],
    title: &str,
) -> Result<(), String> {
    let csv = csv(records).map_err(|e| format!("summary.csv: {e}"))?;
    let [c, j, h] = ids;
    outputs
        .write(c, csv.as_bytes())
        .map_err(|e| e.to_string())?;
    outputs
        .write(j, json(records).as_bytes())
        .map_err(|e| e.to_string())?;
    outputs
        .write(h, html(records, title).as_bytes())
        .map_err(|e| e.to_string())
}

/// Writes `summary.csv`, `summary.json` and `report.html` into `out`, all or none.
pub fn write(out: &Path, records: &[Record], title: &str) -> Result<(), String> {
    let mut outputs = Outputs::new();
    let ids = declare(&mut outputs, out).map_err(|e| e.to_string())?;
    stage(&mut outputs, ids, records, title)?;
    outputs.commit().map(drop).map_err(|e| e.to_string())
}
