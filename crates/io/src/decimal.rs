//! Numbers as text, fast and exactly as Rust's `Display` writes them.
//!
//! The text writers (OBJ, ASCII PLY, XYZ, CSV) print millions of numbers; with
//! `write!("{}")` formatting them was most of an OBJ export (#37: 2.58 M
//! vertices with normals, 1.7 s of 2 s). [`push_f64`] takes the shortest
//! round-trip digits from `zmij` (Schubfach, the float printer serde_json
//! uses) and lays them out as `Display` does — plain decimal, no exponent,
//! `-0` for negative zero — so files stay byte-identical to those written
//! before. The two differ in one case: when the value lies exactly halfway
//! between the two nearest shortest decimals (1 + 2⁻¹⁷ = 1.00000762939453125
//! between …312 and …313), `zmij` rounds to even and `Display` up; such
//! values are detected exactly (integer arithmetic on the mantissa) and
//! printed by `Display`. A property test compares the two on random bit
//! patterns, dyadic rationals (where the halfway cases live) and edge cases.
//! Integers go through `itoa`.

/// Appends `v` as `format!("{v}")` would.
pub fn push_f64(out: &mut Vec<u8>, v: f64) {
    if !v.is_finite() {
        out.extend_from_slice(if v.is_nan() {
            b"NaN"
        } else if v > 0.0 {
            b"inf"
        } else {
            b"-inf"
        });
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(v).as_bytes();
    let (negative, text) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    // mantissa [. fraction] [e exponent] → significant digits and the position
    // of the decimal point among them.
    let (mantissa, exponent) = match text.iter().position(|&c| c == b'e' || c == b'E') {
        Some(e) => (&text[..e], parse_exponent(&text[e + 1..])),
        None => (text, 0),
    };
    let mut digits = [0u8; 32];
    let mut n = 0;
    let mut point = None;
    for &c in mantissa {
        if c == b'.' {
            point = Some(n);
        } else {
            digits[n] = c;
            n += 1;
        }
    }
    let mut point = point.unwrap_or(n) as i32 + exponent;
    let mut digits = &digits[..n];
    while let Some((b'0', rest)) = digits.split_first() {
        digits = rest;
        point -= 1;
    }
    while let Some((b'0', rest)) = digits.split_last() {
        digits = rest;
    }
    let len = digits.len() as i32;
    if !digits.is_empty() && !lower_of_a_tie(v.abs(), digits, point - len) {
        use std::io::Write as _;
        let _ = write!(out, "{v}");
        return;
    }
    if negative {
        out.push(b'-');
    }
    if digits.is_empty() {
        out.push(b'0');
        return;
    }
    if point <= 0 {
        out.extend_from_slice(b"0.");
        out.resize(out.len() + (-point) as usize, b'0');
        out.extend_from_slice(digits);
    } else if point >= len {
        out.extend_from_slice(digits);
        out.resize(out.len() + (point - len) as usize, b'0');
    } else {
        out.extend_from_slice(&digits[..point as usize]);
        out.push(b'.');
        out.extend_from_slice(&digits[point as usize..]);
    }
}

/// `false` when `v` (positive, finite, non-zero) might be exactly
/// (D + ½) × 10^q for the digits D: the halfway case where the shortest
/// printers part ways (`Display` rounds up, `zmij` to even) — or when the
/// check's integers would not fit, so the caller falls back to `Display`.
/// `true` when it certainly is not.
fn lower_of_a_tie(v: f64, digits: &[u8], q: i32) -> bool {
    let d = digits
        .iter()
        .fold(0u128, |d, &c| d * 10 + u128::from(c - b'0'));
    let odd = 2 * d + 1; // < 2⁵⁸ for at most 17 digits
    // v = m × 2^e exactly.
    let bits = v.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32;
    let fraction = u128::from(bits & ((1 << 52) - 1));
    let (m, e) = if exponent == 0 {
        (fraction, -1074)
    } else {
        (fraction | 1 << 52, exponent - 1075)
    };
    // Is m × 2^(e+1) × 10^(−q) = 2D + 1?
    let r = -q;
    if !(0..=32).contains(&r) || !(-1100..=74).contains(&e) {
        return false; // out of the checked range: let Display decide
    }
    let scaled = m * 5u128.pow(r as u32); // < 2^53 × 5^32 < 2^128
    let shift = e + 1 + r;
    let equal = if shift >= 0 {
        shift < 64
            && scaled
                .checked_shl(shift as u32)
                .is_some_and(|l| l >> shift == scaled && l == odd)
    } else {
        let s = (-shift) as u32;
        s < 128 && scaled.trailing_zeros() >= s && scaled >> s == odd
    };
    !equal
}

fn parse_exponent(text: &[u8]) -> i32 {
    let (sign, digits) = match text.split_first() {
        Some((b'-', rest)) => (-1, rest),
        Some((b'+', rest)) => (1, rest),
        _ => (1, text),
    };
    sign * digits
        .iter()
        .fold(0i32, |e, &d| e * 10 + i32::from(d - b'0'))
}

/// Writes `count` records to `w` in order, each formatted by `record(i,
/// buffer)`: blocks of records are formatted on every core, a bounded number
/// at a time (about 32 MB of text), and written as they come.
pub(crate) fn write_records(
    w: &mut dyn std::io::Write,
    count: usize,
    record: impl Fn(usize, &mut Vec<u8>) + Sync,
) -> std::io::Result<()> {
    use rayon::prelude::*;
    const BLOCK: usize = 16 * 1024;
    const ROUND: usize = 32;
    let blocks = count.div_ceil(BLOCK);
    for first in (0..blocks).step_by(ROUND) {
        let texts: Vec<Vec<u8>> = (first..blocks.min(first + ROUND))
            .into_par_iter()
            .map(|b| {
                let mut text = Vec::with_capacity(BLOCK * 48);
                for i in b * BLOCK..count.min((b + 1) * BLOCK) {
                    record(i, &mut text);
                }
                text
            })
            .collect();
        for text in texts {
            w.write_all(&text)?;
        }
    }
    Ok(())
}

/// Appends `v` in decimal.
pub fn push_u64(out: &mut Vec<u8>, v: u64) {
    out.extend_from_slice(itoa::Buffer::new().format(v).as_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn same(v: f64) {
        let mut out = Vec::new();
        push_f64(&mut out, v);
        assert_eq!(String::from_utf8(out).unwrap(), format!("{v}"), "{v:e}");
    }

    #[test]
    fn edge_cases_print_as_display_does() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            1e-7,
            1.5e-10,
            123456789.0,
            1e21,
            1e22,
            1.7976931348623157e308,
            5e-324,
            -2.2250738585072014e-308,
            0.99025248,
            -0.9933307926829269,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            100.0,
            1e15,
            1e16,
            1e17,
            0.3,
            2.0 / 3.0,
            1.0 + 2f64.powi(-17),
            1.2694181358531043e15,
            1232545756755474.2,
        ] {
            same(v);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn any_bits_print_as_display_does(bits in any::<u64>()) {
            same(f64::from_bits(bits));
        }

        #[test]
        fn coordinates_print_as_display_does(v in -1e4f64..1e4) {
            same(v);
        }

        /// Dyadic rationals j / 2^k: the values whose exact decimals are
        /// short enough to fall halfway between two shortest candidates.
        #[test]
        fn dyadic_rationals_print_as_display_does(j in 1u64..(1 << 40), k in 0i32..60, sign in any::<bool>()) {
            let v = j as f64 * 2f64.powi(-k);
            same(if sign { -v } else { v });
        }
    }

    #[test]
    fn integers() {
        let mut out = Vec::new();
        push_u64(&mut out, 0);
        out.push(b' ');
        push_u64(&mut out, u64::MAX);
        assert_eq!(out, b"0 18446744073709551615");
    }
}
