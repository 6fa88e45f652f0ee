//! Exact text for f64 coefficients: C99 hexadecimal floats (`0x1.8p+0` = 1.5).
//!
//! Coefficient files store every fitted number this way so that a value read
//! back is bit-for-bit the value the fit produced; a decimal comment beside it
//! is for people.

use std::fmt;

/// `x` as a hexadecimal float, shortest mantissa (`0x1.8p+0`, `-0x1p-3`, `0x0p+0`,
/// `inf`, `-inf`). NaN is written `nan` (and refused by [`parse`]).
pub fn format(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    let sign = if x.is_sign_negative() { "-" } else { "" };
    if x.is_infinite() {
        return format!("{sign}inf");
    }
    let bits = x.to_bits();
    let exp_bits = ((bits >> 52) & 0x7ff) as i64;
    let frac = bits & ((1u64 << 52) - 1);
    if exp_bits == 0 && frac == 0 {
        return format!("{sign}0x0p+0");
    }
    let (lead, exp) = if exp_bits == 0 { (0, -1022) } else { (1, exp_bits - 1023) };
    let mut digits = format!("{frac:013x}");
    while digits.ends_with('0') {
        digits.pop();
    }
    let dot = if digits.is_empty() { String::new() } else { format!(".{digits}") };
    let esign = if exp >= 0 { "+" } else { "-" };
    format!("{sign}0x{lead}{dot}p{esign}{}", exp.abs())
}

/// Why a string is not a hexadecimal float.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HexfError(pub String);

impl fmt::Display for HexfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "'{}' is not a hexadecimal float like 0x1.8p+0", self.0)
    }
}

impl std::error::Error for HexfError {}

/// Parses what [`format`] writes (any mantissa length up to 13 hex digits after
/// the point, leading digit 0 or 1), exactly.
pub fn parse(s: &str) -> Result<f64, HexfError> {
    let err = || HexfError(s.to_string());
    let (neg, rest) = match s.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, s.strip_prefix('+').unwrap_or(s)),
    };
    let signed = |v: f64| if neg { -v } else { v };
    if rest == "inf" {
        return Ok(signed(f64::INFINITY));
    }
    let rest = rest.strip_prefix("0x").or_else(|| rest.strip_prefix("0X")).ok_or_else(err)?;
    let (mant, exp) = rest.split_once(['p', 'P']).ok_or_else(err)?;
    let exp: i64 = exp.parse().map_err(|_| err())?;
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let lead: u64 = match int {
        "0" => 0,
        "1" => 1,
        _ => return Err(err()),
    };
    if frac.len() > 13 || !frac.chars().all(|c| c.is_ascii_hexdigit()) {
        return Err(err());
    }
    let frac_bits = if frac.is_empty() { 0 } else { u64::from_str_radix(frac, 16).map_err(|_| err())? };
    let m = (lead << 52) | (frac_bits << (4 * (13 - frac.len())));
    if m == 0 {
        return Ok(signed(0.0));
    }
    if !(-1074..=1023).contains(&exp) {
        return Err(err());
    }
    // m · 2^(exp − 52), scaled in two exact steps so subnormals come out right.
    let e = exp - 52;
    let half = e / 2;
    let v = (m as f64) * 2f64.powi(half as i32) * 2f64.powi((e - half) as i32);
    if !v.is_finite() {
        return Err(err());
    }
    Ok(signed(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_exactly() {
        let xs = [
            0.0,
            -0.0,
            1.0,
            1.5,
            -0.8405,
            std::f64::consts::PI,
            1e-300,
            f64::MIN_POSITIVE,
            5e-324,
            1.7e308,
            0.1 + 0.2,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        for x in xs {
            let s = format(x);
            let y = parse(&s).unwrap();
            assert_eq!(x.to_bits(), y.to_bits(), "{x} -> {s} -> {y}");
        }
        assert_eq!(format(1.5), "0x1.8p+0");
        assert_eq!(format(-0.125), "-0x1p-3");
        assert_eq!(format(0.0), "0x0p+0");
    }

    #[test]
    fn refuses_garbage() {
        for s in ["", "1.5", "0x2p+0", "0x1.8", "0x1.gp+0", "nan", "0x1.00000000000001p+0", "0x1p+5000"] {
            assert!(parse(s).is_err(), "{s}");
        }
    }
}
