//! The film's sensor as pbrt-v4's RGB film makes it from its settings (`PixelSensor` and
//! `WhiteBalance` in pbrt-v4's `film.cpp`): the imaging ratio, the white balance from a
//! daylight illuminant to sRGB's white and the cap on a sample's largest component, as the
//! library's [`Sensor`]. Both scene formats build their films' sensors here: pbrt-v4's `Film`
//! directive (`pbrt::sensor` reads its parameters) and the YAML camera's film keys, so that
//! a scene records light the same in either. What each setting means is in `pbrt::sensor`'s
//! notes.

use rayforge::camera::Sensor;
use rayforge::shading::spectrum::{
    linear_srgb_to_xyz, planck, spectrum_to_xyz, xyz_to_linear_srgb,
};
use rayforge::Color;

/// sRGB's white (D65) as pbrt-v4's colour space gives it.
const D65_XY: [f64; 2] = [0.3127, 0.3290];

/// Bradford's cone responses from XYZ, and back (pbrt-v4's `LMSFromXYZ`, `XYZFromLMS`).
const LMS_FROM_XYZ: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];
const XYZ_FROM_LMS: [[f64; 3]; 3] = [
    [0.986993, -0.147054, 0.159963],
    [0.432305, 0.51836, 0.0492912],
    [-0.00852866, 0.0400428, 0.968487],
];

/// pbrt-v4's `cie1931` sensor (see the module's notes): every sample times the imaging ratio
/// `ratio`, white-balanced from the daylight of `temperature` kelvin to sRGB's white (0: not
/// balanced), each sample capped at `max_component` (infinite: not capped). The cap is
/// applied where pbrt-v4's `RGBFilm::AddSample` applies it: to the sample in the sensor's
/// space, which `PixelSensor::ToSensorRGB` has already multiplied by the imaging ratio, and
/// before the white balance and the conversion to the output colour space (the film's
/// `outputRGBFromSensorRGB`, applied when a pixel is read). That space is XYZ for this
/// sensor, so the cap bounds the largest of X, Y and Z times the ratio, not the largest sRGB
/// channel; either way the whole sample is scaled, its hue kept. What the YAML scenes' film
/// keys give too. The caller has checked `ratio` above 0 and finite, `temperature` 0 or
/// above and finite, `max_component` above 0; the error is a balance with no colour to
/// balance from, for the caller to place.
pub(crate) fn cie1931(ratio: f64, temperature: f64, max_component: f64) -> Result<Sensor, String> {
    let basis = [
        Color::new(1.0, 0.0, 0.0),
        Color::new(0.0, 1.0, 0.0),
        Color::new(0.0, 0.0, 1.0),
    ];
    let rows_of = |column: &dyn Fn(Color) -> Color| {
        let [r, g, b] = basis.map(column);
        [
            [r.red, g.red, b.red],
            [r.green, g.green, b.green],
            [r.blue, g.blue, b.blue],
        ]
    };
    let out_of_range = || format!("a white balance of {temperature} K is out of range");
    let sensor = if temperature == 0.0 {
        scaled(ratio)
    } else {
        let white = daylight_xy(temperature).ok_or_else(|| {
            format!("a white balance of {temperature} K has no colour to balance from")
        })?;
        let balance = white_balance(white, D65_XY);
        let column = |c: Color| xyz_to_linear_srgb(apply(&balance, linear_srgb_to_xyz(c))) * ratio;
        Sensor::from_rows(rows_of(&column)).ok_or_else(out_of_range)?
    };
    // The sensor's own space: XYZ times the imaging ratio.
    let measure = |c: Color| {
        let [x, y, z] = linear_srgb_to_xyz(c);
        Color::new(x, y, z) * ratio
    };
    sensor
        .with_max_component(max_component, rows_of(&measure))
        .ok_or_else(out_of_range)
}

/// The sensor that scales by `ratio`.
pub(crate) fn scaled(ratio: f64) -> Sensor {
    let mut rows = Sensor::IDENTITY.rows();
    for (i, row) in rows.iter_mut().enumerate() {
        row[i] = ratio;
    }
    Sensor::from_rows(rows).unwrap_or(Sensor::IDENTITY)
}

/// The chromaticity of pbrt-v4's daylight illuminant `Spectra::D(t)`: the CIE daylight locus
/// at the correlated temperature `t × 1.4388 / 1.4380` (the CIE's change of the second
/// radiation constant), a blackbody's at it below 4000 K. `None` when the blackbody gives no
/// light to measure (temperatures far below any scene's).
pub fn daylight_xy(t: f64) -> Option<[f64; 2]> {
    let cct = t * 1.4388 / 1.4380;
    if cct < 4000.0 {
        let [x, y, z] = spectrum_to_xyz(|l| planck(l, cct));
        let sum = x + y + z;
        return (sum > 0.0 && sum.is_finite()).then(|| [x / sum, y / sum]);
    }
    let x = if cct <= 7000.0 {
        -4.607e9 / cct.powi(3) + 2.9678e6 / (cct * cct) + 0.09911e3 / cct + 0.244063
    } else {
        -2.0064e9 / cct.powi(3) + 1.9018e6 / (cct * cct) + 0.24748e3 / cct + 0.23704
    };
    Some([x, -3.0 * x * x + 2.870 * x - 0.275])
}

/// pbrt-v4's `WhiteBalance`: the matrix of XYZ that takes the white of chromaticity `from`
/// to the white `to`, each cone response of Bradford's space scaled by the ratio of theirs.
pub fn white_balance(from: [f64; 2], to: [f64; 2]) -> [[f64; 3]; 3] {
    let xyz = |[x, y]: [f64; 2]| [x / y, 1.0, (1.0 - x - y) / y];
    let (src, dst) = (
        apply(&LMS_FROM_XYZ, xyz(from)),
        apply(&LMS_FROM_XYZ, xyz(to)),
    );
    let mut scaled = LMS_FROM_XYZ;
    for (row, i) in scaled.iter_mut().zip(0..3) {
        for v in row.iter_mut() {
            *v *= dst[i] / src[i];
        }
    }
    multiply(&XYZ_FROM_LMS, &scaled)
}

/// The matrix `m` applied to `v`.
fn apply(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

/// The product `a · b`.
fn multiply(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The balance takes its source white to its target white exactly, and pbrt-v4's
    /// daylight of 6500 K (correlated 6504 K, the CIE's D65) is sRGB's white.
    #[test]
    fn the_balance_takes_the_illuminants_white_to_the_colour_spaces() {
        for t in [2800.0, 4500.0, 6500.0, 9000.0] {
            let from = daylight_xy(t).unwrap();
            let m = white_balance(from, D65_XY);
            let xyz = |[x, y]: [f64; 2]| [x / y, 1.0, (1.0 - x - y) / y];
            let out = apply(&m, xyz(from));
            // Within the rounding of the inverse matrix as pbrt-v4 gives it (six digits).
            for (a, b) in out.iter().zip(xyz(D65_XY)) {
                assert!((a - b).abs() < 1e-5, "{t}: {out:?}");
            }
        }
        let d65 = daylight_xy(6500.0).unwrap();
        assert!(
            (d65[0] - 0.3127).abs() < 5e-4 && (d65[1] - 0.3290).abs() < 5e-4,
            "{d65:?}"
        );
    }
}
