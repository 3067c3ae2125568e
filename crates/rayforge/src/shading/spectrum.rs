//! Spectral quantities turned into the renderer's linear sRGB, as pbrt-v4 turns them for an
//! RGB film: blackbody emitters, named glasses' refractive indices and named metals.
//!
//! rayforge renders in RGB, so a spectrum becomes three numbers once, when a scene is read:
//! - **Blackbody** `T`: Planck's law, normalised so that its peak (at Wien's wavelength) is 1
//!   as pbrt-v4's `BlackbodySpectrum` is, integrated against the CIE 1931 colour-matching
//!   functions over 360–830 nm and divided by the integral of `ȳ` (pbrt-v4's
//!   `SpectrumToXYZ`), then taken to linear sRGB by the standard XYZ → sRGB (D65) matrix. The
//!   colour-matching functions are the analytic multi-lobe fit of Wyman, Sloan and Shirley
//!   ("Simple Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2013),
//!   within about 1 % of the tabulated functions, not the tables themselves. pbrt-v4 further
//!   divides a light's spectrum by its luminance (`SpectrumToPhotometric`) so that `scale`
//!   and `power` mean what they say: [`blackbody_xyz`]`(t)`'s `y` is that luminance.
//! - **Glass** (`glass-BK7`, `glass-BAF10`, `glass-FK51A`, `glass-LASF9`, `glass-F5`,
//!   `glass-F10`, `glass-F11`): pbrt-v4 samples wavelengths and, where the index varies, ends
//!   all but one of a path's wavelengths at the glass (dispersion). A dielectric here has one
//!   index, so a glass is given its index at 550 nm, near the peak of the eye's sensitivity
//!   and the centre of the visible range, where pbrt-v4's surviving wavelengths average out;
//!   dispersion (coloured fringes) is not rendered. The index comes from each glass's
//!   published Sellmeier coefficients (Schott's catalogue: N-BK7, N-BAF10, N-FK51A, N-LASF9,
//!   SF5, SF10, SF11, the glasses pbrt-v4's named spectra are measured from).
//! - **Metals** (`metal-Ag`, `-Al`, `-Au`, `-Cu`, each `-eta` and `-k`): the RGB reductions
//!   of the `bsdf::metals` table, which come from the same kind of measured spectra reduced
//!   to RGB; `metal-CuZn`, `metal-MgO` and `metal-TiO2` are not in it (`None`).

use super::bsdf::metal;
use crate::color::Color;

/// One lobe of the Wyman–Sloan–Shirley fit: a Gaussian of mean `mu` with widths `below` and
/// `above` on either side.
fn lobe(lambda: f64, mu: f64, below: f64, above: f64) -> f64 {
    let sigma = if lambda < mu { below } else { above };
    let t = (lambda - mu) / sigma;
    (-0.5 * t * t).exp()
}

/// The CIE 1931 2° colour-matching functions `(x̄, ȳ, z̄)` at `lambda` nanometres, by the
/// multi-lobe fit of Wyman, Sloan and Shirley 2013.
pub fn cie_1931(lambda: f64) -> [f64; 3] {
    let x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
        - 0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    [x, y, z]
}

/// CIE XYZ to linear sRGB (D65 white), the standard matrix.
pub fn xyz_to_linear_srgb(xyz: [f64; 3]) -> Color {
    let [x, y, z] = xyz;
    Color::new(
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    )
}

/// Linear sRGB to CIE XYZ, the inverse of [`xyz_to_linear_srgb`].
pub fn linear_srgb_to_xyz(c: Color) -> [f64; 3] {
    [
        0.412_456_4 * c.red + 0.357_576_1 * c.green + 0.180_437_5 * c.blue,
        0.212_672_9 * c.red + 0.715_152_2 * c.green + 0.072_175_0 * c.blue,
        0.019_333_9 * c.red + 0.119_192_0 * c.green + 0.950_304_1 * c.blue,
    ]
}

/// The wavelengths integrated over (nanometres), as pbrt-v4's `Lambda_min`/`Lambda_max`.
const LAMBDA_MIN: f64 = 360.0;
const LAMBDA_MAX: f64 = 830.0;

/// `∫ s(λ) (x̄, ȳ, z̄) dλ / ∫ ȳ dλ` over 360–830 nm in steps of 1 nm: pbrt-v4's
/// `SpectrumToXYZ`, so that a spectrum of 1 everywhere has `Y = 1`.
pub fn spectrum_to_xyz(s: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut y_integral = 0.0;
    let steps = (LAMBDA_MAX - LAMBDA_MIN) as usize;
    for i in 0..=steps {
        let lambda = LAMBDA_MIN + i as f64;
        let cmf = cie_1931(lambda);
        let v = s(lambda);
        for (total, c) in sum.iter_mut().zip(cmf) {
            *total += v * c;
        }
        y_integral += cmf[1];
    }
    sum.map(|t| t / y_integral)
}

/// Planck's law: the spectral radiance of a blackbody at `t` kelvin, at `lambda` nanometres
/// (W sr⁻¹ m⁻³); 0 for a temperature that is not positive.
pub fn planck(lambda: f64, t: f64) -> f64 {
    if t.is_nan() || t <= 0.0 {
        return 0.0;
    }
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda * 1e-9;
    let b = 2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * t)).exp() - 1.0));
    if b.is_finite() {
        b
    } else {
        0.0
    }
}

/// The XYZ of pbrt-v4's `blackbody` spectrum at `t` kelvin: Planck's law divided by its value
/// at the peak wavelength `2.897 771 955 × 10⁻³ m K / t` (so the spectrum's maximum is 1).
pub fn blackbody_xyz(t: f64) -> [f64; 3] {
    let peak = planck(2.897_771_955e-3 / t * 1e9, t);
    if peak.is_nan() || peak <= 0.0 {
        return [0.0; 3];
    }
    spectrum_to_xyz(|lambda| planck(lambda, t) / peak)
}

/// The linear sRGB of pbrt-v4's normalised `blackbody` spectrum at `t` kelvin (see the
/// [module](self)); a channel outside the sRGB gamut (blue below about 1900 K) is held at 0.
pub fn blackbody(t: f64) -> Color {
    let c = xyz_to_linear_srgb(blackbody_xyz(t));
    Color::new(c.red.max(0.0), c.green.max(0.0), c.blue.max(0.0))
}

/// A glass's Sellmeier coefficients `B₁, B₂, B₃` and `C₁, C₂, C₃` (µm²).
type Sellmeier = ([f64; 3], [f64; 3]);

/// pbrt-v4's named glasses and the Schott glasses they are measured from.
const GLASSES: &[(&str, Sellmeier)] = &[
    (
        "glass-BK7",
        (
            [1.039_612_12, 0.231_792_344, 1.010_469_45],
            [0.006_000_698_67, 0.020_017_914_4, 103.560_653],
        ),
    ),
    (
        "glass-BAF10",
        (
            [1.585_149_5, 0.143_559_385, 1.085_212_69],
            [0.009_266_812_82, 0.042_448_980_5, 105.613_573],
        ),
    ),
    (
        "glass-FK51A",
        (
            [0.971_247_817, 0.216_901_417, 0.904_651_666],
            [0.004_723_019_95, 0.015_357_561_2, 168.681_33],
        ),
    ),
    (
        "glass-LASF9",
        (
            [2.000_295_47, 0.298_926_886, 1.806_918_43],
            [0.012_142_601_7, 0.053_873_623_6, 156.530_829],
        ),
    ),
    (
        "glass-F5",
        (
            [1.524_818_89, 0.187_085_527, 1.427_290_15],
            [0.011_254_756, 0.058_899_539_2, 129.141_675],
        ),
    ),
    (
        "glass-F10",
        (
            [1.621_539_02, 0.256_287_842, 1.644_475_52],
            [0.012_224_145_7, 0.059_573_677_5, 147.468_793],
        ),
    ),
    (
        "glass-F11",
        (
            [1.737_596_95, 0.313_747_346, 1.898_781_01],
            [0.013_188_707, 0.062_306_814_2, 155.236_29],
        ),
    ),
];

/// The names [`glass_index`] knows.
pub const GLASS_NAMES: &[&str] = &[
    "glass-BK7",
    "glass-BAF10",
    "glass-FK51A",
    "glass-LASF9",
    "glass-F5",
    "glass-F10",
    "glass-F11",
];

/// The wavelength (nm) at which a named glass's single index is taken (see the
/// [module](self)).
pub const GLASS_WAVELENGTH: f64 = 550.0;

/// A named glass's refractive index at `lambda` nanometres, by its Sellmeier equation
/// `n² = 1 + Σ Bᵢ λ² / (λ² − Cᵢ)` (λ in µm); `None` for an unknown name.
pub fn glass_index_at(name: &str, lambda: f64) -> Option<f64> {
    let (_, (b, c)) = GLASSES.iter().find(|(n, _)| *n == name)?;
    let l2 = (lambda * 1e-3).powi(2);
    let n2 = 1.0 + (0..3).map(|i| b[i] * l2 / (l2 - c[i])).sum::<f64>();
    Some(n2.sqrt())
}

/// A named glass's one refractive index for an RGB render: at [`GLASS_WAVELENGTH`].
pub fn glass_index(name: &str) -> Option<f64> {
    glass_index_at(name, GLASS_WAVELENGTH)
}

/// pbrt-v4's named metal spectra (`metal-Cu-eta` and `metal-Cu-k`, or the stem `metal-Cu`)
/// as the complex index `(η, κ)` per RGB channel; `None` for the metals the table lacks.
pub fn pbrt_metal(name: &str) -> Option<(Color, Color)> {
    let stem = name
        .strip_suffix("-eta")
        .or_else(|| name.strip_suffix("-k"))
        .unwrap_or(name);
    let element = stem.strip_prefix("metal-")?;
    match element {
        "Ag" | "Al" | "Au" | "Cu" => metal(element),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chromaticity(xyz: [f64; 3]) -> (f64, f64) {
        let s = xyz[0] + xyz[1] + xyz[2];
        (xyz[0] / s, xyz[1] / s)
    }

    /// The Planckian locus (CIE 1931 chromaticities of blackbodies, as tabulated in colour
    /// science references) to within the fit's accuracy.
    #[test]
    fn blackbodies_lie_on_the_planckian_locus() {
        for (t, x, y) in [
            (2700.0, 0.4599, 0.4106),
            (4000.0, 0.3805, 0.3768),
            (6500.0, 0.3135, 0.3236),
        ] {
            let (cx, cy) = chromaticity(blackbody_xyz(t));
            assert!(
                (cx - x).abs() < 3e-3 && (cy - y).abs() < 3e-3,
                "{t} K: ({cx}, {cy}) vs ({x}, {y})"
            );
        }
    }

    #[test]
    fn a_6500_kelvin_blackbody_is_nearly_white_and_2700_is_warm() {
        let white = blackbody(6500.0);
        let m = white.max_channel();
        assert!(white.to_array().iter().all(|c| c / m > 0.9), "{white:?}");
        let warm = blackbody(2700.0);
        assert!(
            warm.red > warm.green && warm.green > warm.blue && warm.blue < 0.5 * warm.red,
            "{warm:?}"
        );
        // Normalised to a peak of 1, the spectrum's luminance is below 1 and positive.
        for t in [1000.0, 2700.0, 6500.0, 20_000.0] {
            let y = blackbody_xyz(t)[1];
            assert!(y > 0.0 && y < 1.0, "{t} K: Y {y}");
        }
        assert_eq!(blackbody(0.0), Color::BLACK);
        assert_eq!(blackbody(f64::NAN), Color::BLACK);
    }

    #[test]
    fn colour_spaces_round_trip_and_white_is_d65() {
        let c = Color::new(0.3, 0.7, 0.1);
        let back = xyz_to_linear_srgb(linear_srgb_to_xyz(c));
        assert!((back - c).max_channel().abs() < 1e-6, "{back:?}");
        let [x, y, z] = linear_srgb_to_xyz(Color::WHITE);
        assert!((x - 0.9505).abs() < 1e-3 && (y - 1.0).abs() < 1e-6 && (z - 1.089).abs() < 1e-3);
        // A flat spectrum is nearly the fit's white (equal energy, E, which is close to D65).
        let e = xyz_to_linear_srgb(spectrum_to_xyz(|_| 1.0));
        assert!((spectrum_to_xyz(|_| 1.0)[1] - 1.0).abs() < 1e-12);
        assert!(e.to_array().iter().all(|v| (v - 1.0).abs() < 0.25), "{e:?}");
    }

    /// Each glass's Sellmeier equation gives its catalogue index at the helium d line
    /// (587.56 nm), and dispersion runs the right way (blue bends more).
    #[test]
    fn named_glasses_have_their_catalogue_indices() {
        for (name, n_d) in [
            ("glass-BK7", 1.5168),
            ("glass-BAF10", 1.6700),
            ("glass-FK51A", 1.4866),
            ("glass-LASF9", 1.8503),
            ("glass-F5", 1.6727),
            ("glass-F10", 1.7283),
            ("glass-F11", 1.7847),
        ] {
            let n = glass_index_at(name, 587.56).expect(name);
            assert!((n - n_d).abs() < 2e-4, "{name}: {n} vs {n_d}");
            assert!(glass_index_at(name, 450.0) > glass_index_at(name, 650.0));
            assert!(GLASS_NAMES.contains(&name));
            let at_550 = glass_index(name).unwrap();
            assert!(at_550 > n && at_550 < n + 0.01, "{name}: {at_550}");
        }
        assert_eq!(GLASS_NAMES.len(), GLASSES.len());
        assert!(glass_index("glass-unobtainium").is_none());
    }

    #[test]
    fn pbrt_metal_names_reach_the_metal_table() {
        assert_eq!(pbrt_metal("metal-Cu-eta"), metal("copper"));
        assert_eq!(pbrt_metal("metal-Au-k"), metal("gold"));
        assert_eq!(pbrt_metal("metal-Al"), metal("aluminium"));
        assert_eq!(pbrt_metal("metal-Ag-eta"), metal("silver"));
        assert!(pbrt_metal("metal-CuZn-eta").is_none());
        assert!(pbrt_metal("Cu").is_none());
    }
}
