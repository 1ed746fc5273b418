//! Tick labels people read: powers of ten with Unicode superscripts on log axes (`10⁻⁴`,
//! `2·10⁻⁴`), plain decimals on linear axes, with a common factor `×10ᵏ` moved into the axis
//! title when the values are very small or very large.

/// `n` in Unicode superscript digits: `-4` ↦ `⁻⁴`.
pub fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

/// A positive value as a power of ten: `10⁻⁴`, or `m·10ᵉ` with a one- or two-digit mantissa
/// (`2·10⁻⁴`, `2.5·10³`) when it is not a power of ten.
pub fn power_of_ten(x: f64) -> String {
    if !(x.is_finite() && x > 0.0) {
        return String::new();
    }
    let mut exponent = x.log10().floor() as i32;
    let mut mantissa = x / 10f64.powi(exponent);
    // 9.9999… is 10: round to two significant digits before deciding.
    mantissa = (mantissa * 10.0).round() / 10.0;
    if mantissa >= 10.0 {
        mantissa /= 10.0;
        exponent += 1;
    }
    if mantissa == 1.0 {
        format!("10{}", superscript(exponent))
    } else {
        format!("{mantissa}·10{}", superscript(exponent))
    }
}

/// The exponent `k` of the factor `10ᵏ` to take out of a linear axis spanning `[lo, hi]`: 0
/// when the largest magnitude is between 10⁻² and 10⁴ (plain numbers read well), otherwise
/// the multiple of 1 that brings it to `[1, 10)`.
pub fn common_exponent(lo: f64, hi: f64) -> i32 {
    let largest = lo.abs().max(hi.abs());
    if !(largest.is_finite() && largest > 0.0) || (1e-2..1e4).contains(&largest) {
        return 0;
    }
    largest.log10().floor() as i32
}

/// An axis title with the factor taken out of its labels: `E_k − E (×10⁻⁴)`.
pub fn scaled_title(title: &str, exponent: i32) -> String {
    if exponent == 0 {
        title.to_string()
    } else {
        format!("{title}, ×10{}", superscript(exponent))
    }
}

/// A plain decimal label for `x` on an axis whose ticks are about `step` apart: as many
/// decimals as the step needs, no exponent, and no `-0`.
pub fn plain(x: f64, step: f64) -> String {
    let decimals = if step > 0.0 && step.is_finite() {
        (-step.log10() - 1e-9).ceil().max(0.0) as usize
    } else {
        2
    };
    let text = format!("{x:.decimals$}");
    let is_zero = text
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.');
    if is_zero {
        text.trim_start_matches('-').to_string()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powers_of_ten_read_as_powers() {
        assert_eq!(power_of_ten(1e-4), "10⁻⁴");
        assert_eq!(power_of_ten(1.0), "10⁰");
        assert_eq!(power_of_ten(1000.0), "10³");
        assert_eq!(power_of_ten(2e-4), "2·10⁻⁴");
        assert_eq!(power_of_ten(2.5e3), "2.5·10³");
        assert_eq!(power_of_ten(9.9999e-6), "10⁻⁵");
        assert_eq!(power_of_ten(1e-16), "10⁻¹⁶");
        assert_eq!(power_of_ten(0.0), "");
    }

    #[test]
    fn linear_labels_are_plain_numbers() {
        assert_eq!(plain(0.4, 0.1), "0.4");
        assert_eq!(plain(12.0, 2.0), "12");
        assert_eq!(plain(-0.0001, 0.1), "0.0");
        assert_eq!(plain(-1.25, 0.05), "-1.25");
        assert_eq!(common_exponent(-3e-4, 2e-4), -4);
        assert_eq!(common_exponent(-1.0, 1.0), 0);
        assert_eq!(common_exponent(0.0, 5e5), 5);
        assert_eq!(scaled_title("E", -4), "E, ×10⁻⁴");
        assert_eq!(scaled_title("q (rad)", 0), "q (rad)");
    }
}
