//! Radians to degrees as rs274 converts them, bit for bit.
//!
//! rs274 (LinuxCNC 2.9) gives `ACOS`, `ASIN` and `ATAN` as `(acos(x) *
//! 180.0) / M_PIl`: a product of doubles (rounded to 53 bits) divided by
//! the `long double` π, which on x86-64 is rounded to a 64-bit significand
//! (the x87's), then to a double where it is stored. The plain
//! `to_degrees` differs from that in the last bit for about one value in
//! three, which a `FIX`, a `MOD` or a comparison after the function can
//! turn into a different move. Here the same steps are worked out exactly
//! in integers. (`SIN`, `COS` and `TAN` take `sinl` of the long double
//! radians, which ger does not reproduce: ARCHITECTURE.md.)

/// `M_PIl`: π to 64 bits, times 2^62.
const PI_64: u128 = 0xC90F_DAA2_2168_C235;

/// `r` in radians to degrees, as rs274 gives `ACOS`, `ASIN` and `ATAN`.
pub fn to_degrees(r: f64) -> f64 {
    let Some((negative, m, e)) = parts(r) else {
        return r.to_degrees();
    };
    // r · 180 is a double product (rounded to 53 bits); brought to 64
    // bits for the quotient by PI_64 to have 64 or 65, and 8 more with
    // the remainder.
    let (n, e) = round(m * 180, e, false, 53);
    let shift = n.leading_zeros() as i32 - 64;
    let n = n << shift;
    let (q, rest) = ((n << 64) / PI_64, (n << 64) % PI_64);
    let (q, rest) = ((q << 8) | ((rest << 8) / PI_64), (rest << 8) % PI_64);
    // n · 2^(e − shift) / (PI_64 · 2^−62), with 72 bits of the quotient.
    let exponent = e - shift + 62 - 64 - 8;
    let (d, de) = round(q, exponent, rest != 0, 64);
    compose(negative, round(d, de, false, 53))
}

/// A normal `x` as its sign, its 53-bit significand and the exponent of
/// its last bit; `None` for 0, subnormals, infinities and NaN (and values
/// so large or small that the result would not be a normal double), left
/// to the plain conversion.
fn parts(x: f64) -> Option<(bool, u128, i32)> {
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if !(64..=2046 - 64).contains(&biased) {
        return None;
    }
    let m = (bits & ((1 << 52) - 1)) | (1 << 52);
    Some((x < 0.0, u128::from(m), biased - 1023 - 52))
}

/// `v` · 2^`e`, with `sticky` set where nonzero bits below `v`'s last were
/// cut, rounded to `bits` significant bits (to nearest, ties to even).
/// `v` has more than `bits` bits whenever `sticky` is set.
fn round(v: u128, e: i32, sticky: bool, bits: u32) -> (u128, i32) {
    let length = 128 - v.leading_zeros();
    if length <= bits {
        return (v, e);
    }
    let cut = length - bits;
    let (kept, rest, half) = (v >> cut, v & ((1 << cut) - 1), 1u128 << (cut - 1));
    let up = rest > half || (rest == half && (sticky || kept & 1 == 1));
    let kept = kept + u128::from(up);
    match kept >> bits {
        0 => (kept, e + cut as i32),
        _ => (kept >> 1, e + cut as i32 + 1),
    }
}

/// The double `±d · 2^e` (`d` below 2^53; the result normal, as [`parts`]
/// leaves only such).
fn compose(negative: bool, (d, e): (u128, i32)) -> f64 {
    // Both factors exact, and so their product.
    let scale = f64::from_bits(((1023 + e) as u64) << 52);
    let v = d as f64 * scale;
    if negative {
        -v
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values from rs274's own arithmetic (C on x86-64, `(r * 180.0) /
    /// M_PIl` stored as double), each one where the plain conversion gives
    /// another double. (The conversion matched C's on 106,003 values,
    /// 33,477 of them where the plain one differs: `acos`, `asin` and
    /// `atan2` of every thousandth in ±1, and 100,000 more.)
    #[test]
    fn conversions_round_as_rs274_does() {
        let degrees = [
            (0x40050a61f4e408beu64, 0x4062d623f819ba52u64),
            (0x400410b5d0ff8ac1, 0x4061f69f43cb5cf5),
            (0xbff2791d757ba5fc, 0xc05089b956987d1a),
            (0xbfedac670561bb50, 0xc04a90a731a61dc4),
        ];
        for (r, bits) in degrees {
            let r = f64::from_bits(r);
            assert_ne!(r.to_degrees().to_bits(), bits, "{r}");
            assert_eq!(to_degrees(r).to_bits(), bits, "{r}");
        }
    }

    /// Where the plain conversion is exact, the emulated one agrees.
    #[test]
    fn right_angles_match_the_plain_conversion() {
        assert_eq!(to_degrees(std::f64::consts::FRAC_PI_2), 90.0);
        assert_eq!(to_degrees(std::f64::consts::PI), 180.0);
        assert_eq!(to_degrees(-std::f64::consts::FRAC_PI_4), -45.0);
        assert_eq!(to_degrees(0.0), 0.0);
    }
}
