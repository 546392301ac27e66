//! Reports written with their words: a typed value serialised by its `Display`.

use std::fmt;

/// Serialises a value by its `Display` (a report's words).
pub(crate) fn as_text<T: fmt::Display, S: serde::Serializer>(
    v: &T,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_str(v)
}

/// Serialises values by their `Display`, as a sequence.
pub(crate) fn as_texts<T: fmt::Display, S: serde::Serializer>(
    v: &[T],
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(ToString::to_string))
}
