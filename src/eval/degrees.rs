//! Radians to degrees as rs274 converts them, bit for bit.
//!
//! rs274 (LinuxCNC 2.9) gives `ACOS`, `ASIN` and `ATAN` as `(acos(x) *
//! 180.0) / M_PIl`: a product of doubles (rounded to 53 bits) divided by
//! the `long double` π, which on x86-64 is rounded to a 64-bit significand
//! (the x87's), then to a double where it is stored. The plain
//! `to_degrees` differs from that in the last bit for about one value in
//! three, which a `FIX`, a `MOD` or a comparison after the function can
//! turn into a different move. Here the same steps are worked out exactly
//! in integers.
//!
//! `SIN`, `COS` and `TAN` are `sinl`, `cosl`, `tanl` of `(x * M_PIl) /
//! 180.0`, the long double radians. Those are worked out exactly as two
//! doubles, and the functions to first order from them: on 123,020 angles
//! (thousandths of a degree, multiples of 30° and 45°, and more) 77–78 %
//! of the sines and cosines and 75 % of the tangents are rs274's to the
//! last bit (the plain `sin(to_radians(x))`: 16–38 %), and every sign is
//! (the plain ones differ in sign on 112 of them, at multiples of 90°).
//! The rest differ by a unit or so in the last place; matching those would
//! take the functions in double-double precision.

/// `M_PIl`: π to 64 bits, times 2^62.
const PI_64: u128 = 0xC90F_DAA2_2168_C235;

/// rs274's `SIN`, `COS` and `TAN` of `x` degrees: `sinl` … of the long
/// double radians, here to first order from its two doubles (`hi + lo`,
/// [`radians`]): the sign and size of the values near 0 at whole
/// multiples of 90° (SIN[180] is −5.0e-20 there, the double sine of
/// the double π is +1.2e-16), and the last bit of most others.
pub fn sin(x: f64) -> f64 {
    let (hi, lo) = radians(x);
    lo.mul_add(hi.cos(), hi.sin())
}

/// See [`sin`].
pub fn cos(x: f64) -> f64 {
    let (hi, lo) = radians(x);
    (-lo).mul_add(hi.sin(), hi.cos())
}

/// See [`sin`]; near 90° and 270°, where the first-order tangent does not
/// hold, the quotient of the two (TAN[90] is −4.0e19 there, the double
/// tangent of the double π/2 +1.6e16).
pub fn tan(x: f64) -> f64 {
    let (hi, lo) = radians(x);
    let t = hi.tan();
    match t.abs() < 1e8 {
        true => lo.mul_add(t.mul_add(t, 1.0), t),
        false => sin(x) / cos(x),
    }
}

/// `x` degrees in radians as rs274 has them, `(x * M_PIl) / 180.0` in
/// long double (each step rounded to a 64-bit significand), as the double
/// nearest it and the (exact) rest.
fn radians(x: f64) -> (f64, f64) {
    let Some((negative, m, e)) = parts(x) else {
        return (x.to_radians(), 0.0);
    };
    // x · π, rounded to 64 bits: m · PI_64 · 2^(e − 62).
    let (p, pe) = round(m * PI_64, e - 62, false, 64);
    // Then / 180, rounded to 64 bits: the quotient has over 100.
    let wide = p << 64;
    let (q, qe) = round(wide / 180, pe - 64, wide % 180 != 0, 64);
    let (d, de) = round(q, qe, false, 53);
    // The rest: q − d · 2^(de − qe), within 11 bits and a sign.
    let rest = (q as i128) - ((d as i128) << (de - qe));
    let (hi, lo) = (compose(false, (d, de)), rest as f64 * power_of_two(qe));
    match negative {
        true => (-hi, -lo),
        false => (hi, lo),
    }
}

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
    // Within 2^±895: every exponent the steps reach is a normal double's.
    if !(128..=2046 - 128).contains(&biased) {
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
    let v = d as f64 * power_of_two(e);
    if negative {
        -v
    } else {
        v
    }
}

/// 2^`e`, a normal double.
fn power_of_two(e: i32) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
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

    /// rs274's values at multiples of 90°, from C (`sinl` … of the long
    /// double radians, as double): their signs are those of the long
    /// double π's error, not the double's.
    #[test]
    fn right_angles_have_rs274s_signs() {
        let cases = [
            (sin(180.0), 0xbbed9cceba3f91f2u64),
            (sin(-180.0), 0x3bed9cceba3f91f2),
            (cos(90.0), 0xbbdd9cceba3f91f2),
            (tan(90.0), 0xc4014a3c09b557b4),
            (tan(180.0), 0x3bed9cceba3f91f2),
            (cos(180.0), (-1.0f64).to_bits()),
            (sin(90.0), 1.0f64.to_bits()),
        ];
        // Near 0 the first order leaves 12 digits (the double sine's own
        // error, 1e-32, against a value of 5e-20): sign and size.
        for (k, (got, want)) in cases.into_iter().enumerate() {
            let want = f64::from_bits(want);
            assert!(
                (got - want).abs() <= want.abs() * 1e-11,
                "case {k}: {got:e}, not {want:e}"
            );
        }
        assert!(180f64.to_radians().sin() > 0.0, "the plain sine differs");
    }

    /// Far from 1, where the steps would leave the doubles' exponents, the
    /// values are the plain ones'.
    #[test]
    fn tiny_and_huge_angles_are_the_plain_ones() {
        for x in [1e-280, -1e-290, 1e280, 5e-324, 2f64.powi(-955)] {
            assert_eq!(sin(x), x.to_radians().sin(), "{x}");
            assert_eq!(to_degrees(x), x.to_degrees(), "{x}");
        }
        // Just inside: the long double steps, still finite and close.
        let x = 2f64.powi(-894);
        assert!((sin(x) / x.to_radians() - 1.0).abs() < 1e-15);
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
