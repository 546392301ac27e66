//! Mutations of the committed inputs for the property tests: a scene's text with one line
//! broken, a plan file with one field broken.
#![allow(dead_code)]

use proptest::sample::Index;
use serde_json::Value;

/// Values that break a field in every way the format can be broken.
pub const ABSURD: [&str; 14] = [
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e30",
    "-1",
    "0",
    "1e-300",
    "\"x\"",
    "true",
    "[]",
    "{}",
    "[1, 2",
    "9999999999999999999999",
];

/// One mutation of a scene's text: replace the value of one `key = value` line with an
/// absurd one, delete a line, duplicate one, or cut the text short.
pub fn mutate_scene(text: &str, line: Index, kind: u8, value: Index, cut: Index) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = line.index(lines.len());
    match kind % 4 {
        0 => {
            if let Some(eq) = lines[i].find('=') {
                let key = lines[i][..eq].to_string();
                lines[i] = format!("{key}= {}", ABSURD[value.index(ABSURD.len())]);
            }
        }
        1 => {
            lines.remove(i);
        }
        2 => {
            let l = lines[i].clone();
            lines.insert(i, l);
        }
        _ => {
            let joined = lines.join("\n");
            let mut at = cut.index(joined.len() + 1);
            while !joined.is_char_boundary(at) {
                at -= 1;
            }
            return joined[..at].to_string();
        }
    }
    lines.join("\n")
}

/// Every leaf (and object member) of a JSON document, as a path of keys and indices.
fn leaves(v: &Value, path: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                path.push(Value::String(k.clone()));
                out.push(path.clone());
                leaves(x, path, out);
                path.pop();
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Value::from(i));
                leaves(x, path, out);
                path.pop();
            }
        }
        _ => out.push(path.clone()),
    }
}

fn at<'a>(v: &'a mut Value, path: &[Value]) -> &'a mut Value {
    path.iter().fold(v, |v, k| match k {
        Value::String(s) => &mut v[s.as_str()],
        Value::Number(n) => &mut v[n.as_u64().unwrap() as usize],
        _ => unreachable!(),
    })
}

/// One mutation of a plan file: a field replaced by an absurd value, or deleted.
pub fn mutate_plan(plan: &Value, leaf: Index, kind: u8, value: Index) -> String {
    let mut all = Vec::new();
    leaves(plan, &mut Vec::new(), &mut all);
    let path = &all[leaf.index(all.len())];
    let mut v = plan.clone();
    let (parent, last) = path.split_at(path.len() - 1);
    if kind % 3 == 0 {
        if let (Value::Object(m), Value::String(k)) = (at(&mut v, parent), &last[0]) {
            m.remove(k);
        }
    } else {
        let text = ABSURD[value.index(ABSURD.len())];
        let replacement = serde_json::from_str(text).unwrap_or(Value::String(text.into()));
        *at(&mut v, path) = replacement;
    }
    serde_json::to_string_pretty(&v).unwrap()
}

/// Values that break an XML attribute of a robot description in every way one can be broken.
pub const ABSURD_ATTRIBUTES: [&str; 16] = [
    "nan",
    "inf",
    "-inf",
    "1e308",
    "1e400",
    "-1",
    "0",
    "1e10",
    "",
    "x",
    "0 0 0",
    "1 2",
    "nan 1 1",
    "1e308 1 1",
    "../../../../dev/zero",
    "package://",
];

/// One mutation of a robot description's text: one attribute's value replaced by an absurd
/// one, a line deleted or duplicated, a line wrapped in 100 000 elements, or the text cut.
pub fn mutate_description(text: &str, at: Index, kind: u8, value: Index) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = at.index(lines.len());
    match kind % 5 {
        0 => {
            let starts: Vec<usize> = text.match_indices("=\"").map(|(k, _)| k + 2).collect();
            let start = starts[at.index(starts.len())];
            let end = start + text[start..].find('"').unwrap();
            let absurd = ABSURD_ATTRIBUTES[value.index(ABSURD_ATTRIBUTES.len())];
            return format!("{}{absurd}{}", &text[..start], &text[end..]);
        }
        1 => {
            lines.remove(i);
        }
        2 => {
            let l = lines[i].clone();
            lines.insert(i, l);
        }
        3 => {
            let deep = 100_000;
            lines[i] = format!("{}{}{}", "<a>".repeat(deep), lines[i], "</a>".repeat(deep));
        }
        _ => {
            let mut at = value.index(text.len() + 1);
            while !text.is_char_boundary(at) {
                at -= 1;
            }
            return text[..at].to_string();
        }
    }
    lines.join("\n")
}
