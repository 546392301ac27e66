//! Text for people: messages that quote user input stay short and readable.

/// `s` cut to at most `max` characters (on a character boundary), with "…" and the number of
/// characters left out when it was longer — for messages that quote a line of input.
pub fn clip(s: &str, max: usize) -> String {
    let count = s.chars().count();
    if count <= max {
        return s.to_string();
    }
    let kept: String = s.chars().take(max).collect();
    format!("{kept}… ({} more characters)", count - kept.chars().count())
}

/// A message whose numbers are readable: every decimal number written with more than 12
/// digits before or after the point (as Rust prints 1e308 or 1e-300 in full) is written in
/// scientific notation instead (`1e308`), with the same value. Other text is unchanged.
pub fn readable_numbers(message: &str) -> String {
    let bytes = message.as_bytes();
    let mut out = String::with_capacity(message.len());
    let mut i = 0;
    while i < bytes.len() {
        // A number starts at a digit that does not continue a word (`ur5e`, `0x1f`).
        let starts = bytes[i].is_ascii_digit()
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if !starts {
            let ch = message[i..].chars().next().expect("on a char boundary");
            out.push(ch);
            i += ch.len_utf8();
            continue;
        }
        let mut j = i;
        while j < bytes.len() && bytes[j].is_ascii_digit() {
            j += 1;
        }
        let int_digits = j - i;
        let mut frac_digits = 0;
        if j + 1 < bytes.len() && bytes[j] == b'.' && bytes[j + 1].is_ascii_digit() {
            j += 1;
            while j < bytes.len() && bytes[j].is_ascii_digit() {
                j += 1;
                frac_digits += 1;
            }
        }
        let token = &message[i..j];
        match token.parse::<f64>() {
            Ok(x) if int_digits > 12 || frac_digits > 12 => out.push_str(&format!("{x:e}")),
            _ => out.push_str(token),
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_numbers_become_scientific_and_keep_their_value() {
        let huge = format!("must be > 0, found -{}", 1e308);
        assert_eq!(readable_numbers(&huge), "must be > 0, found -1e308");
        let tiny = format!("scale {}", 5e-324);
        assert_eq!(readable_numbers(&tiny), "scale 5e-324");
        let mixed = "ur5e at 0.5 m, 1234567890123456789 rad, v1.2.3";
        assert_eq!(
            readable_numbers(mixed),
            "ur5e at 0.5 m, 1.2345678901234568e18 rad, v1.2.3"
        );
        assert_eq!(readable_numbers("θ = 12.5° — ok"), "θ = 12.5° — ok");
    }

    #[test]
    fn clipping_counts_characters_not_bytes() {
        assert_eq!(clip("ab", 5), "ab");
        assert_eq!(clip("ééééé", 2), "éé… (3 more characters)");
    }
}
