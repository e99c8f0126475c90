//! Number formatting: every number of the output goes through here. Values
//! are put on a decimal grid (`q` units of 10^-decimals) once, so that what
//! is compared is what is printed; the digits are written without `format!`
//! (the printer's hot loop).

pub fn push_int(out: &mut Vec<u8>, n: i64) {
    let mut buf = [0u8; 24];
    let mut start = digits_before(&mut buf, 24, n.unsigned_abs());
    if n < 0 {
        start -= 1;
        buf[start] = b'-';
    }
    out.extend_from_slice(&buf[start..]);
}

/// Write the decimal digits of `n` (at least one) into `buf`, ending just
/// before `end`, two at a time; returns where they start.
fn digits_before(buf: &mut [u8], mut end: usize, mut n: u64) -> usize {
    while n >= 100 {
        let pair = usize::from((n % 100) as u8) * 2;
        n /= 100;
        end -= 2;
        buf[end..end + 2].copy_from_slice(&PAIRS[pair..pair + 2]);
    }
    if n >= 10 {
        let pair = n as usize * 2;
        end -= 2;
        buf[end..end + 2].copy_from_slice(&PAIRS[pair..pair + 2]);
    } else {
        end -= 1;
        buf[end] = b'0' + n as u8;
    }
    end
}

/// 10^0 to 10^18.
const TENS: [u64; 19] = {
    let mut tens = [1u64; 19];
    let mut i = 1;
    while i < 19 {
        tens[i] = tens[i - 1] * 10;
        i += 1;
    }
    tens
};

/// "00" to "99".
const PAIRS: &[u8; 200] = b"0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// `x` rounded half away from zero, as `f64::round` (without its libm
/// call); saturates like `as i64` outside the range of `i64`.
pub fn round_to_int(x: f64) -> i64 {
    // Below 2^52 the truncation and the fraction `x - t` are exact.
    if x.abs() < 4.5e15 {
        let t = x as i64;
        let fraction = x - t as f64;
        // Without branches: which way a value rounds is as good as random
        // (`1.462 * 1000.0` is a hair under 1462), so a branch would be
        // guessed wrong half the time.
        t + i64::from(fraction >= 0.5) - i64::from(fraction <= -0.5)
    } else {
        x.round() as i64
    }
}

/// How close (in the output's unit) to a tie at the last decimal a value
/// counts as the tie; with many decimals, at most a thousandth of a step.
const TIE: f64 = 1e-9;
const TIE_STEPS: f64 = 1e-3;

/// `v` on the grid of `scale` steps per unit (10^decimals), a tie rounded
/// half away from zero, and a value within [`TIE`] of a tie taken as the
/// tie: the same coordinate computed two ways (38.78749999999 and
/// 38.78750000001) prints the same, `38.788`, everywhere.
pub fn to_grid(v: f64, scale: f64) -> i64 {
    let x = v * scale;
    round_to_int(x + tie_band(scale).copysign(x))
}

/// [`TIE`] in steps of the grid.
fn tie_band(scale: f64) -> f64 {
    (TIE * scale).min(TIE_STEPS)
}

/// A number with a decimal point and at most `decimals` decimals, trailing
/// zeros removed: `1.`, `-0.25`, `12.5`.
pub fn push_fixed_bytes(out: &mut Vec<u8>, v: f64, decimals: usize) {
    let decimals = decimals.min(9);
    let scale = 10f64.powi(decimals as i32);
    if !v.is_finite() || v.abs() >= 1e12 || (v * scale).abs() >= 1e18 {
        out.extend_from_slice(format!("{v:.decimals$}").as_bytes());
        return;
    }
    push_scaled(out, to_grid(v, scale), decimals);
}

/// `q` × 10^-`decimals` (at most 18) as [`push_fixed_bytes`] writes it.
/// The usual numbers from tables ([`push_thousandths`]); the others
/// written right to left into one buffer: the fraction's digits (its
/// trailing zeros dropped first), the point, the integer's digits (at least
/// one) and the sign; then copied once.
pub fn push_scaled(out: &mut Vec<u8>, q: i64, decimals: usize) {
    // A millimetre program's numbers: three decimals, under a thousand.
    let n = q.unsigned_abs();
    if decimals == 3 && n < 1_000_000 {
        return push_thousandths(out, n, q < 0);
    }
    // An inch program's: four decimals, under a hundred.
    if decimals == 4 && n < 1_000_000 {
        return push_ten_thousandths(out, n, q < 0);
    }
    // The usual decimals as constants: their divisions become multiplications.
    match decimals {
        3 => push_scaled_by(out, q, 3),
        4 => push_scaled_by(out, q, 4),
        2 => push_scaled_by(out, q, 2),
        5 => push_scaled_by(out, q, 5),
        6 => push_scaled_by(out, q, 6),
        _ => push_scaled_by(out, q, decimals),
    }
}

/// `n` thousandths (under a million), negative or not, as
/// [`push_scaled_by`] writes it: its integer and its fraction looked up
/// in [`INTEGERS`] and [`FRACTIONS`], and put together in a register, a
/// byte each, then stored at once (no digit is computed, and nothing just
/// stored is read back).
#[inline]
fn push_thousandths(out: &mut Vec<u8>, n: u64, negative: bool) {
    // (Under a thousand already: the `%` spares the bounds check.)
    let (integer, fraction) = ((n / 1000) as usize % 1000, (n % 1000) as usize);
    // At most 8 bytes: the sign, three digits, the point and three more.
    push_number(out, negative, INTEGERS[integer], FRACTIONS[fraction]);
}

/// `n` ten-thousandths (under a hundred units), as [`push_thousandths`]
/// writes thousandths: the first three decimals looked up as three, the
/// fourth after them where it is not a zero.
#[inline]
fn push_ten_thousandths(out: &mut Vec<u8>, n: u64, negative: bool) {
    // (Under a hundred: the `%` spares the bounds check.)
    let (integer, fraction) = ((n / 10_000) as usize % 1000, n % 10_000);
    let (three, fourth) = ((fraction / 10) as usize, fraction % 10);
    let fraction = if fourth == 0 {
        FRACTIONS[three]
    } else {
        // The point, three digits and the fourth.
        let digits = u64::from(PADDED[three]) | (u64::from(b'0') + fourth) << 24;
        u64::from(b'.') | digits << 8 | 5 << 56
    };
    // At most 8 bytes: the sign, two digits, the point and four more.
    push_number(out, negative, INTEGERS[integer], fraction);
}

/// The sign if `negative`, then the texts of two table entries (an
/// integer's and a fraction's), a byte each in one register, stored at
/// once: eight bytes, then cut to theirs (at most eight together).
#[inline(always)]
fn push_number(out: &mut Vec<u8>, negative: bool, integer: u64, fraction: u64) {
    let mut text = if negative { u64::from(b'-') } else { 0 };
    let mut len = u64::from(negative);
    text |= (integer & TEXT) << (8 * len);
    len += integer >> 56;
    text |= (fraction & TEXT) << (8 * len);
    len += fraction >> 56;
    push_packed(out, text, len as usize);
}

/// The first `len` bytes of `text` (at most eight, the first the lowest):
/// the eight stored at once, then the vector cut to theirs.
#[inline(always)]
fn push_packed(out: &mut Vec<u8>, text: u64, len: usize) {
    let at = out.len();
    out.extend_from_slice(&text.to_le_bytes());
    out.truncate(at + len);
}

/// `N<line> `, the word of a source line: from the tables, as
/// [`push_thousandths`] writes a number, up to 999,999.
pub fn push_line_word(out: &mut Vec<u8>, line: u32) {
    if line >= 1_000_000 {
        out.push(b'N');
        push_int(out, i64::from(line));
        out.push(b' ');
        return;
    }
    let (thousands, rest) = ((line / 1000) as usize, (line % 1000) as usize);
    let digits = if thousands == 0 {
        INTEGERS[rest]
    } else {
        let high = INTEGERS[thousands];
        let len = high >> 56;
        (high & TEXT) | u64::from(PADDED[rest]) << (8 * len) | (len + 3) << 56
    };
    let len = digits >> 56;
    // At most 8 bytes: `N`, six digits, the space.
    let text = u64::from(b'N') | (digits & TEXT) << 8 | u64::from(b' ') << (8 * (len + 1));
    push_packed(out, text, len as usize + 2);
}

/// 0 to 999 in three digits (`000`, `042`), a byte each from the lowest.
const PADDED: [u32; 1000] = {
    let mut table = [0u32; 1000];
    let mut n = 0;
    while n < 1000 {
        let digits = [n / 100, n / 10 % 10, n % 10];
        let mut i = 0;
        while i < 3 {
            table[n] |= (b'0' as u32 + digits[i] as u32) << (8 * i);
            i += 1;
        }
        n += 1;
    }
    table
};

/// The text bytes of an entry of [`INTEGERS`] or [`FRACTIONS`]; its top
/// byte is their count.
const TEXT: u64 = (1 << 56) - 1;

/// 0 to 999 in digits (`0`, `7`, `42`, `999`), a byte each from the
/// lowest, and their count in the top byte.
const INTEGERS: [u64; 1000] = {
    let mut table = [0u64; 1000];
    let mut n = 0;
    while n < 1000 {
        let digits = [(n / 100) as u64, (n / 10 % 10) as u64, (n % 10) as u64];
        let first = if n >= 100 {
            0
        } else if n >= 10 {
            1
        } else {
            2
        };
        let (mut text, mut len, mut i) = (0u64, 0u64, first);
        while i < 3 {
            text |= (b'0' as u64 + digits[i]) << (8 * len);
            len += 1;
            i += 1;
        }
        table[n] = text | len << 56;
        n += 1;
    }
    table
};

/// The point and 0 to 999 thousandths, trailing zeros dropped (`.`,
/// `.5`, `.25`, `.125`, `.007`), as [`INTEGERS`] holds its text.
const FRACTIONS: [u64; 1000] = {
    let mut table = [0u64; 1000];
    let mut n = 0;
    while n < 1000 {
        let digits = [(n / 100) as u64, (n / 10 % 10) as u64, (n % 10) as u64];
        let width = if n == 0 {
            0
        } else if n % 100 == 0 {
            1
        } else if n % 10 == 0 {
            2
        } else {
            3
        };
        let (mut text, mut i) = (b'.' as u64, 0);
        while i < width {
            text |= (b'0' as u64 + digits[i]) << (8 * (i + 1));
            i += 1;
        }
        table[n] = text | ((width as u64 + 1) << 56);
        n += 1;
    }
    table
};

#[inline(always)]
fn push_scaled_by(out: &mut Vec<u8>, q: i64, decimals: usize) {
    // Zeros: the fraction's leading ones are left in place.
    let mut buf = [b'0'; 48];
    let mut i = buf.len();
    let mut n = q.unsigned_abs();
    let decimals = decimals.min(18);
    if decimals > 0 {
        let scale = TENS[decimals];
        let (mut fraction, mut width) = (n % scale, decimals);
        n /= scale;
        if fraction != 0 {
            while fraction % 100 == 0 {
                fraction /= 100;
                width -= 2;
            }
            if fraction % 10 == 0 {
                fraction /= 10;
                width -= 1;
            }
            // `width` digits, the leading ones zeros.
            digits_before(&mut buf, i, fraction);
            i -= width;
        }
    }
    i -= 1;
    buf[i] = b'.';
    i = digits_before(&mut buf, i, n);
    if q < 0 {
        i -= 1;
        buf[i] = b'-';
    }
    out.extend_from_slice(&buf[i..]);
}

/// [`push_fixed_bytes`] onto a `String`.
pub fn push_fixed(out: &mut String, v: f64, decimals: usize) {
    let mut bytes = Vec::with_capacity(24);
    push_fixed_bytes(&mut bytes, v, decimals);
    out.push_str(&String::from_utf8_lossy(&bytes));
}

#[cfg(test)]
mod tests {
    use super::{push_fixed, push_int, push_scaled, round_to_int};

    fn fixed(v: f64, d: usize) -> String {
        let mut s = String::new();
        push_fixed(&mut s, v, d);
        s
    }

    #[test]
    fn numbers_always_have_a_point() {
        assert_eq!(fixed(1.0, 3), "1.");
        assert_eq!(fixed(-0.25, 3), "-0.25");
        assert_eq!(fixed(12.0005, 3), "12.001");
        assert_eq!(fixed(-0.0001, 3), "0.");
        assert_eq!(fixed(0.05, 4), "0.05");
        assert_eq!(fixed(1234.5678, 4), "1234.5678");
    }

    #[test]
    fn the_same_value_computed_two_ways_prints_the_same() {
        // issue 48: a pocket lap from Y38.787 to Y38.788
        let (below, above) = (38.7875 - 3e-12, 38.7875 + 3e-12);
        assert_eq!(fixed(below, 3), "38.788");
        assert_eq!(fixed(above, 3), "38.788");
        assert_eq!(fixed(-below, 3), "-38.788");
        assert_eq!(fixed(0.1 + 0.2 - 0.3 + 0.0005, 3), "0.001");
        assert_eq!(fixed(1.00045, 4), "1.0005");
        // a value that is not a tie is not moved
        assert_eq!(fixed(38.78749, 3), "38.787");
        assert_eq!(fixed(38.7875 - 2e-9, 3), "38.787");
    }

    #[test]
    fn rounding_is_half_away_from_zero_like_f64_round() {
        let ties = [0.5, 1.5, 2.5, -0.5, -1.5, -2.5, 0.49999999999999994];
        let edges = [4503599627370495.5, -4503599627370495.5, 4.5e15, 1e18, -1e19];
        for x in ties.into_iter().chain(edges) {
            assert_eq!(round_to_int(x), x.round() as i64, "{x}");
        }
    }

    /// The printer formats integers on the output grid; it must print
    /// what rounding the value and printing its digits would.
    #[test]
    fn fixed_point_matches_rounding_then_printing() {
        fn reference(v: f64, d: usize) -> String {
            let scale = 10u64.pow(d as u32);
            let x = v * scale as f64;
            let n = (x + super::tie_band(scale as f64).copysign(x)).round() as i64;
            let sign = if n < 0 { "-" } else { "" };
            let n = n.unsigned_abs();
            let fraction = format!("{:0width$}", n % scale, width = d);
            format!("{sign}{}.{}", n / scale, fraction.trim_end_matches('0'))
        }
        let mut random = crate::test_random::Random::new(0x2545_f491_4f6c_dd1d);
        for i in 0..20_000 {
            // Values over many magnitudes, both signs.
            let unit = (random.bits() >> 11) as f64 / (1u64 << 53) as f64;
            let v = (unit - 0.5) * 10f64.powi((i % 13) as i32 - 4);
            let d = i % 10;
            assert_eq!(fixed(v, d), reference(v, d), "{v} with {d} decimals");
        }
    }

    /// Every number `push` writes from the tables (the first million of
    /// units of 10^-`decimals`), both signs, after text already in the
    /// buffer, as the digits computed write it.
    fn tables_write_the_computed_digits(push: fn(&mut Vec<u8>, u64, bool), decimals: usize) {
        let (mut tables, mut computed) = (Vec::new(), Vec::new());
        for n in 0..1_000_000u64 {
            for negative in [false, n > 0] {
                tables.clear();
                computed.clear();
                tables.push(b'X');
                computed.push(b'X');
                push(&mut tables, n, negative);
                let q = if negative { -(n as i64) } else { n as i64 };
                super::push_scaled_by(&mut computed, q, decimals);
                assert_eq!(tables, computed, "{q} with {decimals} decimals");
            }
        }
    }

    #[test]
    fn thousandths_from_the_tables_are_the_computed_digits() {
        tables_write_the_computed_digits(super::push_thousandths, 3);
    }

    #[test]
    fn ten_thousandths_from_the_tables_are_the_computed_digits() {
        tables_write_the_computed_digits(super::push_ten_thousandths, 4);
    }

    /// Integers and grid values at the ends of `i64`, with every number of
    /// decimals, as the standard formatting writes them; after text already
    /// in the buffer, which stays.
    #[test]
    fn extremes_are_written_whole() {
        let values = [0, 1, -1, 9, 10, 99, 100, -100, 1_000_000_007];
        let ends = [i64::MAX, i64::MIN, i64::MAX - 1, i64::MIN + 1];
        for q in values.into_iter().chain(ends) {
            let mut out = b"X".to_vec();
            push_int(&mut out, q);
            assert_eq!(out, format!("X{q}").into_bytes());
            for decimals in 0..=18u32 {
                let scale = 10i128.pow(decimals);
                let (int, fraction) = (i128::from(q) / scale, i128::from(q) % scale);
                let digits = format!("{:0width$}", fraction.abs(), width = decimals as usize);
                let sign = if q < 0 { "-" } else { "" };
                let expected = format!("Y{sign}{}.{}", int.abs(), digits.trim_end_matches('0'));
                let mut out = b"Y".to_vec();
                push_scaled(&mut out, q, decimals as usize);
                assert_eq!(String::from_utf8(out).unwrap(), expected, "{q} {decimals}");
            }
        }
    }
}
