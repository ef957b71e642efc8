//! Numbers as the outputs write them: CSV cells in shortest round-trip form (`zmij`), table cells
//! to [`DIGITS`] significant digits, correctly rounded (as `{:.6e}` rounds), each written once
//! into the output with nothing allocated.

/// Significant digits of the table's numbers.
pub const DIGITS: usize = 7;

/// `v` in shortest round-trip form (`zmij`), appended to `out`.
pub fn push_float(out: &mut Vec<u8>, v: f64) {
    let mut b = zmij::Buffer::new();
    out.extend_from_slice(b.format(v).as_bytes());
}

/// `v` with [`DIGITS`] significant digits: fixed notation from 1e-4 to 1e7, else scientific
/// (`1.234568e303`); zeros as `0`; `-` for a value that is not finite.
pub fn significant(v: f64) -> String {
    let mut out = Vec::new();
    push_significant(&mut out, v, 0);
    String::from_utf8_lossy(&out).into_owned()
}

/// [`significant`] appended to `out`, right-aligned in `width` characters: the cell's bytes are
/// laid out in place (spaces, then each character written once).
pub fn push_significant(out: &mut Vec<u8>, v: f64, width: usize) {
    let (negative, n, exp) = match v {
        0.0 => return pad(out, b"0", width),
        _ if !v.is_finite() => return pad(out, b"-", width),
        _ => {
            let (n, exp) = rounded(v);
            (v < 0.0, n, exp)
        }
    };
    let len = number_len(negative, exp);
    let start = out.len() + width.saturating_sub(len);
    out.resize(start + len, b' ');
    write_number(&mut out[start..], negative, n, exp);
}

/// `text` right-aligned in `width`.
fn pad(out: &mut Vec<u8>, text: &[u8], width: usize) {
    out.resize(out.len() + width.saturating_sub(text.len()), b' ');
    out.extend_from_slice(text);
}

/// The length of [`write_number`]'s text.
fn number_len(negative: bool, exp: i32) -> usize {
    usize::from(negative)
        + match exp {
            0..=5 => DIGITS + 1,
            6 => DIGITS,
            -4..=-1 => DIGITS + 1 + (-exp) as usize,
            _ => DIGITS + 2 + usize::from(exp < 0) + exponent_digits(exp),
        }
}

fn exponent_digits(exp: i32) -> usize {
    match exp.unsigned_abs() {
        0..=9 => 1,
        10..=99 => 2,
        _ => 3,
    }
}

/// Seven digits `n` (in [10^6, 10^7)) with the decimal exponent `exp` of the first, signed, into
/// `dst` (exactly [`number_len`] long): fixed notation (decimals enough for all seven) for
/// exponents -4 to 6, else `d.dddddde<exp>`; each character written once.
fn write_number(dst: &mut [u8], negative: bool, n: u32, exp: i32) {
    let mut at = 0;
    let mut put = |c: u8| {
        if let Some(d) = dst.get_mut(at) {
            *d = c;
        }
        at += 1;
    };
    if negative {
        put(b'-');
    }
    // The seven digits, first to last, by division by the constant 10 (a multiplication).
    let mut digits = [b'0'; DIGITS];
    let mut rest = n;
    for d in digits.iter_mut().rev() {
        *d = b'0' + (rest % 10) as u8;
        rest /= 10;
    }
    let digit = |k: usize| digits[k];
    match exp {
        0..=6 => {
            for k in 0..DIGITS {
                put(digit(k));
                if k == exp as usize && k + 1 < DIGITS {
                    put(b'.');
                }
            }
        }
        -4..=-1 => {
            put(b'0');
            put(b'.');
            for _ in 0..(-exp - 1) {
                put(b'0');
            }
            (0..DIGITS).for_each(|k| put(digit(k)));
        }
        _ => {
            put(digit(0));
            put(b'.');
            (1..DIGITS).for_each(|k| put(digit(k)));
            put(b'e');
            if exp < 0 {
                put(b'-');
            }
            let e = exp.unsigned_abs();
            for p in [100, 10, 1].into_iter().skip(3 - exponent_digits(exp)) {
                put(b'0' + ((e / p) % 10) as u8);
            }
        }
    }
}

/// |v| (finite, not zero) correctly rounded to [`DIGITS`] significant digits: the digits as an
/// integer in [10^6, 10^7) and the decimal exponent `e` of the first. `m = |v| · 10^(6−e)` in f64
/// (10^k exact for |k| ≤ 22, so `m` is within 1e-9 of its true value), rounded to the nearest
/// integer, is the answer unless `m` lies within 1e-6 of a rounding midpoint; there, and for
/// exponents beyond that range, the exact decimal expansion decides (`{:.6e}`, by the standard
/// library).
fn rounded(v: f64) -> (u32, i32) {
    let a = v.abs();
    let binary = ((a.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    // floor(binary · log10 2) (78913 / 2^18 = 0.30103…; the shift floors negatives too): floor
    // of log10 a, or one below it.
    let mut e = ((binary * 78913) >> 18) as i32;
    for _ in 0..2 {
        let k = 6 - e;
        if !(-22..=22).contains(&k) {
            return exact(v);
        }
        let m = if k >= 0 {
            a * POW10[k as usize]
        } else {
            a / POW10[(-k) as usize]
        };
        if m >= 1e7 {
            e += 1;
            continue;
        }
        if m < 1e6 {
            e -= 1;
            continue;
        }
        // m in [1e6, 1e7): truncation is its floor (no libm call).
        let whole = m as u32;
        let fraction = m - f64::from(whole);
        if (fraction - 0.5).abs() < 1e-6 {
            return exact(v);
        }
        let r = whole + u32::from(fraction > 0.5);
        return if r >= 10_000_000 {
            (1_000_000, e + 1)
        } else {
            (r, e)
        };
    }
    exact(v)
}

/// 10^k, exact in f64 for k ≤ 22.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// [`rounded`] by the standard library's exact formatting (`{:.6e}`).
fn exact(v: f64) -> (u32, i32) {
    let sci = format!("{:.*e}", DIGITS - 1, v.abs());
    let s = sci.as_bytes();
    let e_at = s.iter().position(|&b| b == b'e').unwrap_or(s.len());
    let exp = std::str::from_utf8(&s[(e_at + 1).min(s.len())..])
        .ok()
        .and_then(|e| e.parse().ok())
        .unwrap_or(0);
    let n = s[..e_at]
        .iter()
        .filter(|b| b.is_ascii_digit())
        .fold(0u32, |n, &d| n * 10 + u32::from(d - b'0'));
    (n, exp)
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn significant_digits() {
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(1.0), "1.000000");
        assert_eq!(significant(123.456789), "123.4568");
        assert_eq!(significant(-0.000001234567), "-1.234567e-6");
        assert_eq!(significant(0.0001234567), "0.0001234567");
        assert_eq!(significant(1e303), "1.000000e303");
        assert_eq!(significant(9.99999999), "10.00000");
        assert_eq!(significant(12345678.0), "1.234568e7");
        assert_eq!(significant(f64::NAN), "-");
        let mut cells = Vec::new();
        for v in [1.5, -2.5e-300, 0.0, f64::INFINITY] {
            super::push_significant(&mut cells, v, 15);
        }
        assert_eq!(
            String::from_utf8(cells).unwrap(),
            "       1.500000 -2.500000e-300              0              -"
        );
    }

    /// The fast path (shortest digits rounded) against the standard library's exact rounding,
    /// over numbers of every magnitude and the ties that matter: 8-digit values ending in 5 and
    /// their neighbours, values with 9 to 17 digits, powers of ten and their neighbours.
    #[test]
    fn rounding_is_the_exact_one() {
        let reference = |v: f64| {
            let exp: i32 = format!("{:.6e}", v)
                .split('e')
                .nth(1)
                .unwrap()
                .parse()
                .unwrap();
            if (-4..7).contains(&exp) {
                let decimals = (6 - exp).max(0) as usize;
                format!("{v:.decimals$}")
            } else {
                format!("{v:.6e}")
            }
        };
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let mut values = Vec::new();
        for _ in 0..200_000 {
            let bits = next();
            let v = f64::from_bits(bits);
            if v.is_finite() && v != 0.0 {
                values.push(v);
            }
            let mantissa = (next() % 90_000_000 + 10_000_000) as f64;
            let scale = 10f64.powi((next() % 40) as i32 - 20);
            let tie = mantissa * scale;
            values.extend([
                tie,
                f64::from_bits(tie.to_bits() + 1),
                f64::from_bits(tie.to_bits() - 1),
            ]);
            let short = ((next() % 9_000_000 + 1_000_000) * 10 + 5) as f64 * scale;
            values.extend([short, -short]);
        }
        for k in -30..30 {
            let p = 10f64.powi(k);
            values.extend([
                p,
                f64::from_bits(p.to_bits() + 1),
                f64::from_bits(p.to_bits() - 1),
            ]);
            values.push(9.9999995 * p);
        }
        for v in values {
            assert_eq!(significant(v), reference(v), "{v:e}");
        }
    }
}
