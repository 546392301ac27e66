//! The shape of an XML document, checked before a recursive reader walks it.
//!
//! URDF is read by `urdf-rs` (RustyXML and serde-xml-rs) and COLLADA by `mesh-loader` (on
//! roxmltree); all of them recurse once per level of element nesting, so a 150 KB file of
//! 20 000 nested elements overflows the stack and aborts the process (and a batch with it).
//! [`check`] scans the text once, in a loop with a counter for a stack, and refuses a
//! document nested deeper than [`Shape::max_depth`] or with more elements than
//! [`Shape::max_elements`]. It does not judge well-formedness (the real reader does, with
//! its own message); it only makes sure the real reader can finish.
//!
//! The scan knows what may hide a `<` or `>` that is not a tag: comments (`<!-- -->`),
//! CDATA sections, processing instructions (`<? ?>`), declarations such as `<!DOCTYPE [..]>`
//! (skipped whole, brackets and quotes counted), and quoted attribute values. Depth counts
//! the markup as written: entities are not expanded (the readers behind it do not expand
//! declared entities either).

use std::fmt;

/// How deep and how large a document may be.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    /// Most levels of element nesting (the root element is level 1).
    pub max_depth: usize,
    /// Most elements (start tags, self-closing ones included).
    pub max_elements: usize,
}

impl Shape {
    /// A robot description: URDF nests 4–6 levels (robot, link, collision, geometry, mesh);
    /// 64 leaves room for any extension, 2 million elements for 200 000 links.
    pub const DESCRIPTION: Shape = Shape {
        max_depth: 64,
        max_elements: 2_000_000,
    };
    /// A COLLADA mesh: node hierarchies of CAD exports nest a few tens of levels; 256 is far
    /// beyond any real file and far below a stack's reach.
    pub const COLLADA: Shape = Shape {
        max_depth: 256,
        max_elements: 8_000_000,
    };
}

/// Why a document was refused.
#[derive(Clone, Debug, PartialEq)]
pub enum XmlError {
    /// An element nested deeper than allowed: its name and line.
    TooDeep {
        /// The element's name.
        element: String,
        /// Its line (1-based).
        line: usize,
        /// The limit.
        max: usize,
    },
    /// More elements than allowed.
    TooManyElements {
        /// The limit.
        max: usize,
    },
    /// A comment, CDATA section, declaration or tag that never ends.
    Unterminated {
        /// What it is (`"comment"`, `"tag"`, …).
        what: &'static str,
        /// The line it starts on (1-based).
        line: usize,
    },
}

impl fmt::Display for XmlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            XmlError::TooDeep { element, line, max } => write!(
                f,
                "element <{element}> on line {line} is nested more than {max} levels deep"
            ),
            XmlError::TooManyElements { max } => write!(f, "more than {max} XML elements"),
            XmlError::Unterminated { what, line } => {
                write!(f, "a {what} starting on line {line} never ends")
            }
        }
    }
}

impl std::error::Error for XmlError {}

/// Checks that `text` nests no deeper and has no more elements than `shape` allows (see the
/// module documentation).
pub fn check(text: &str, shape: Shape) -> Result<(), XmlError> {
    let b = text.as_bytes();
    let line_at = |i: usize| 1 + b[..i].iter().filter(|&&c| c == b'\n').count();
    let find = |from: usize, pat: &[u8]| -> Option<usize> {
        b.get(from..)?
            .windows(pat.len())
            .position(|w| w == pat)
            .map(|k| from + k + pat.len())
    };
    let unterminated = |what, at| XmlError::Unterminated {
        what,
        line: line_at(at),
    };
    let (mut i, mut depth, mut elements) = (0, 0usize, 0usize);
    while let Some(k) = b.get(i..).and_then(|r| r.iter().position(|&c| c == b'<')) {
        let at = i + k;
        let rest = &b[at..];
        i = if rest.starts_with(b"<!--") {
            find(at + 4, b"-->").ok_or_else(|| unterminated("comment", at))?
        } else if rest.starts_with(b"<![CDATA[") {
            find(at + 9, b"]]>").ok_or_else(|| unterminated("CDATA section", at))?
        } else if rest.starts_with(b"<?") {
            find(at + 2, b"?>").ok_or_else(|| unterminated("processing instruction", at))?
        } else if rest.starts_with(b"<!") {
            declaration_end(b, at).ok_or_else(|| unterminated("declaration", at))?
        } else {
            let end = tag_end(b, at).ok_or_else(|| unterminated("tag", at))?;
            if rest.starts_with(b"</") {
                depth = depth.saturating_sub(1);
            } else {
                elements += 1;
                if elements > shape.max_elements {
                    return Err(XmlError::TooManyElements {
                        max: shape.max_elements,
                    });
                }
                if b[end - 2] != b'/' {
                    depth += 1;
                    if depth > shape.max_depth {
                        let name = rest[1..]
                            .iter()
                            .take_while(|c| !c.is_ascii_whitespace() && !b"/>".contains(c))
                            .take(64)
                            .map(|&c| c as char)
                            .collect();
                        return Err(XmlError::TooDeep {
                            element: name,
                            line: line_at(at),
                            max: shape.max_depth,
                        });
                    }
                }
            }
            end
        };
    }
    Ok(())
}

/// The index after the `>` closing the tag that starts at `at`, quoted values skipped.
fn tag_end(b: &[u8], at: usize) -> Option<usize> {
    let mut quote = None;
    for (k, &c) in b.iter().enumerate().skip(at + 1) {
        match (quote, c) {
            (None, b'"' | b'\'') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, b'>') => return Some(k + 1),
            _ => {}
        }
    }
    None
}

/// The index after the `>` closing the declaration (`<!DOCTYPE …>`) that starts at `at`:
/// brackets of an internal subset and quoted literals skipped, comments inside it too.
fn declaration_end(b: &[u8], at: usize) -> Option<usize> {
    let (mut k, mut brackets, mut quote) = (at + 2, 0usize, None);
    while k < b.len() {
        let c = b[k];
        match (quote, c) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, b'"' | b'\'') => quote = Some(c),
            (None, b'<') if b[k..].starts_with(b"<!--") => {
                k = b[k + 4..].windows(3).position(|w| w == b"-->")? + k + 4 + 2;
            }
            (None, b'[') => brackets += 1,
            (None, b']') => brackets = brackets.saturating_sub(1),
            (None, b'>') if brackets == 0 => return Some(k + 1),
            _ => {}
        }
        k += 1;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nested(levels: usize) -> String {
        let mut s = String::from("<robot name=\"r\">");
        s.push_str(&"<a>".repeat(levels));
        s.push_str(&"</a>".repeat(levels));
        s.push_str("</robot>");
        s
    }

    #[test]
    fn deep_nesting_is_refused_without_recursing() {
        // 100 000 levels: a recursive reader overflows the test thread's 2 MiB stack here.
        let err = check(&nested(100_000), Shape::DESCRIPTION).unwrap_err();
        assert_eq!(
            err.to_string(),
            "element <a> on line 1 is nested more than 64 levels deep"
        );
        assert!(check(&nested(63), Shape::DESCRIPTION).is_ok());
        assert!(check(&nested(64), Shape::DESCRIPTION).is_err());
    }

    #[test]
    fn element_count_is_bounded() {
        let many = format!("<robot>{}</robot>", "<link/>".repeat(1000));
        let small = Shape {
            max_depth: 8,
            max_elements: 500,
        };
        assert_eq!(
            check(&many, small).unwrap_err(),
            XmlError::TooManyElements { max: 500 }
        );
        assert!(check(&many, Shape::DESCRIPTION).is_ok());
    }

    #[test]
    fn markup_hidden_in_comments_cdata_quotes_and_doctype_is_not_counted() {
        let doc =
            "<?xml version=\"1.0\"?>\n<!DOCTYPE robot [\n<!ENTITY x \"<a>\">\n<!-- ] > -->\n]>\n\
                   <robot name=\"a>b\"><!-- <a><a> --><![CDATA[<a><a>]]>\n\
                   <link name='<a>'><visual/></link></robot>";
        let one = Shape {
            max_depth: 2,
            max_elements: 10,
        };
        assert_eq!(check(doc, one), Ok(()));
        let err = check(
            doc,
            Shape {
                max_depth: 1,
                ..one
            },
        )
        .unwrap_err();
        assert_eq!(
            err,
            XmlError::TooDeep {
                element: "link".to_string(),
                line: 7,
                max: 1
            }
        );
        assert!(matches!(
            check("<robot><!-- never", one),
            Err(XmlError::Unterminated {
                what: "comment",
                line: 1
            })
        ));
    }
}
