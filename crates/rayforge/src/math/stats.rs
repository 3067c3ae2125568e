//! Statistics for the tests of the samplers: Pearson's chi-square test, with its p-value from
//! the regularised upper incomplete gamma function. Test-only (compiled under `cfg(test)`).

/// `ln Γ(x)` for `x > 0`, by Lanczos' approximation (g = 7, nine terms), accurate to about
/// 15 digits, which is ample for p-values.
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const COEFFICIENTS: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x) Γ(1 − x) = π / sin(πx).
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + G + 0.5;
    let series = COEFFICIENTS[1..]
        .iter()
        .enumerate()
        .fold(COEFFICIENTS[0], |acc, (i, c)| {
            acc + c / (x + i as f64 + 1.0)
        });
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// `Q(a, x) = Γ(a, x) / Γ(a)`, the regularised upper incomplete gamma function: by its power
/// series for `P = 1 − Q` below `x = a + 1`, by its continued fraction (Lentz's method) above.
pub(crate) fn gamma_q(a: f64, x: f64) -> f64 {
    assert!(a > 0.0 && x >= 0.0, "gamma_q({a}, {x})");
    if x == 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let mut term = 1.0 / a;
        let mut sum = term;
        let mut n = 1.0;
        while term.abs() > sum.abs() * 1e-16 && n < 10_000.0 {
            term *= x / (a + n);
            sum += term;
            n += 1.0;
        }
        (1.0 - sum * prefactor).max(0.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let i = i as f64;
            let an = -i * (i - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (prefactor * h).clamp(0.0, 1.0)
    }
}

/// The probability that a chi-square variable with `dof` degrees of freedom exceeds
/// `statistic`: the p-value of a chi-square test whose bins a caller has pooled itself.
pub(crate) fn chi_square_tail(statistic: f64, dof: usize) -> f64 {
    gamma_q(dof as f64 / 2.0, statistic / 2.0)
}

/// The p-value of Pearson's chi-square test that `counts` were drawn with the probabilities
/// `expected` (which sum to 1). Bins expecting fewer than five samples are pooled with their
/// neighbours (the test's approximation needs that many); a sample in a bin of probability
/// zero gives 0 at once.
pub(crate) fn chi_square_p_value(counts: &[u64], expected: &[f64]) -> f64 {
    assert_eq!(counts.len(), expected.len());
    let n: u64 = counts.iter().sum();
    let n = n as f64;
    let mut statistic = 0.0;
    let mut bins = 0usize;
    let (mut pooled_count, mut pooled_expected) = (0.0, 0.0);
    for (&count, &p) in counts.iter().zip(expected) {
        if p <= 0.0 {
            if count > 0 {
                return 0.0;
            }
            continue;
        }
        pooled_count += count as f64;
        pooled_expected += p * n;
        if pooled_expected >= 5.0 {
            statistic += (pooled_count - pooled_expected).powi(2) / pooled_expected;
            bins += 1;
            pooled_count = 0.0;
            pooled_expected = 0.0;
        }
    }
    if pooled_expected > 0.0 {
        statistic += (pooled_count - pooled_expected).powi(2) / pooled_expected;
        bins += 1;
    }
    if bins < 2 {
        return 1.0;
    }
    gamma_q((bins - 1) as f64 / 2.0, statistic / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_function_matches_known_values() {
        assert!(ln_gamma(1.0).abs() < 1e-14);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-13);
        assert!((ln_gamma(0.25) - 3.625_609_908_221_908f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn the_chi_square_tail_matches_closed_forms() {
        // Two degrees of freedom: an exponential tail.
        for x in [0.1_f64, 1.0, 5.0, 30.0] {
            assert!(
                (chi_square_tail(x, 2) - (-x / 2.0).exp()).abs() < 1e-13,
                "{x}"
            );
        }
        // Q(1/2, x/2) = erfc(√(x/2)); the median of χ²₁ is 0.454936…
        assert!((chi_square_tail(0.454_936_423_119_572_8, 1) - 0.5).abs() < 1e-9);
        // Four degrees of freedom: e^(−x/2)(1 + x/2).
        for x in [0.5_f64, 3.0, 12.0, 60.0] {
            let q = (-x / 2.0).exp() * (1.0 + x / 2.0);
            assert!((chi_square_tail(x, 4) - q).abs() < 1e-13, "{x}");
        }
    }

    #[test]
    fn p_values_match_tables() {
        // Q(1, x) = e^-x.
        for x in [0.1, 1.0, 2.5, 10.0] {
            assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-13, "{x}");
        }
        // The 5 % critical values of chi-square with 1, 10 and 100 degrees of freedom.
        for (dof, critical) in [(1.0, 3.841_459), (10.0, 18.307_04), (100.0, 124.342_1)] {
            let p = gamma_q(dof / 2.0, critical / 2.0);
            assert!((p - 0.05).abs() < 1e-5, "{dof}: {p}");
        }
    }

    #[test]
    fn chi_square_accepts_a_fit_and_rejects_a_misfit() {
        let expected = [0.25, 0.25, 0.5];
        assert!(chi_square_p_value(&[250, 250, 500], &expected) > 0.99);
        assert!(chi_square_p_value(&[400, 100, 500], &expected) < 1e-6);
        assert_eq!(chi_square_p_value(&[1, 0], &[0.0, 1.0]), 0.0);
    }
}
