//! The film's sensor as pbrt-v4's RGB film has it (`PixelSensor::Create` in `film.cpp`):
//! what the film records of each sample's radiance.
//!
//! - **The imaging ratio**, the exposure time × `iso` / 100, scales every sample: the
//!   exposure time is the camera's `shutterclose` − `shutteropen` (1 − 0 by default), `iso`
//!   the film's (100 by default), so a file that gives neither renders as it is, `iso` 200
//!   twice as bright, a shutter open half as long half as bright. A shutter that does not
//!   open (a time of 0 or less) is an error, as in pbrt-v4.
//! - **White balance**, `whitebalance` (kelvin; 0, the default for the `cie1931` sensor, is
//!   none): pbrt-v4's von Kries adaptation in Bradford's cone space (its `WhiteBalance`) from
//!   the white of the CIE daylight illuminant at that temperature (pbrt-v4's `Spectra::D`:
//!   the correlated temperature `T × 1.4388 / 1.4380`, a blackbody's below 4000 K) to the
//!   colour space's white, D65 for sRGB. The daylight white is the CIE daylight locus's
//!   chromaticity, which the illuminant's tabulated spectrum is made to have (pbrt-v4
//!   integrates that spectrum, within about 10⁻³ of it); a blackbody's is integrated as
//!   `shading::spectrum` integrates spectra. rayforge renders linear sRGB, so the map is
//!   sRGB → XYZ, the adaptation, XYZ → sRGB, times the imaging ratio.
//! - **`maxcomponentvalue`** (infinite, none, by default; above 0): each sample scaled down
//!   as a whole where its largest component is above the value, pbrt-v4's guard against
//!   fireflies, measured where pbrt-v4 measures it: in the sensor's space after the imaging
//!   ratio, before the white balance (see [`cie1931`]).
//! - **`sensor`**: `cie1931` (the default) is pbrt-v4's XYZ sensor, read exactly as above.
//!   pbrt-v4's measured camera sensors (`canon_eos_5d` and the rest) are rendered as the
//!   `cie1931` sensor with the same imaging ratio and white balance (6500 K unless given, as
//!   pbrt-v4 defaults a camera sensor), with a warning: pbrt-v4 fits a matrix from the
//!   camera's own response curves, which rayforge does not have. Other names are refused.

use super::reader::Entity;
use crate::error::SceneError;
use rayforge::camera::Sensor;
use rayforge::shading::spectrum::{
    linear_srgb_to_xyz, planck, spectrum_to_xyz, xyz_to_linear_srgb,
};
use rayforge::Color;

/// The camera sensors pbrt-v4 has measured curves for (`sensor` names other than `cie1931`).
const CAMERA_SENSORS: &[&str] = &[
    "canon_eos_100d",
    "canon_eos_1dx_mkii",
    "canon_eos_200d",
    "canon_eos_200d_mkii",
    "canon_eos_5d",
    "canon_eos_5d_mkii",
    "canon_eos_5d_mkiii",
    "canon_eos_5d_mkiv",
    "canon_eos_5ds",
    "canon_eos_m",
    "hasselblad_l1d_20c",
    "nikon_d810",
    "nikon_d850",
    "sony_ilce_6400",
    "sony_ilce_7m3",
    "sony_ilce_7rm3",
    "sony_ilce_9",
];

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

/// The sensor of the film `film` behind the camera `camera` (either absent: pbrt-v4's
/// defaults), warnings added to `warnings`.
pub fn sensor(
    film: Option<&Entity>,
    camera: Option<&Entity>,
    warnings: &mut Vec<SceneError>,
) -> Result<Sensor, SceneError> {
    let exposure = match camera {
        None => 1.0,
        Some(camera) => {
            let params = &camera.params;
            let open = params.float_at("shutteropen")?;
            let close = params.float_at("shutterclose")?;
            let time = close.map_or(1.0, |(v, _)| v) - open.map_or(0.0, |(v, _)| v);
            if !(time > 0.0 && time.is_finite()) {
                let message = format!(
                    "the shutter is open for {time} (shutterclose − shutteropen), and a shutter \
                     that does not open gives a black image"
                );
                return Err(match close.or(open) {
                    Some((_, p)) => p.error(message),
                    None => camera.error(message),
                });
            }
            time
        }
    };
    let Some(film) = film else {
        return Ok(scaled(exposure));
    };
    let params = &film.params;
    let iso = match params.float_at("iso")? {
        None => 100.0,
        Some((v, p)) if !(v > 0.0 && v.is_finite()) => {
            return Err(p.error(format!("an ISO is above 0, found {v}")))
        }
        Some((v, _)) => v,
    };
    let ratio = exposure * iso / 100.0;
    if !ratio.is_finite() {
        return Err(film.error(format!(
            "the imaging ratio, the exposure time {exposure} × iso {iso} / 100, is past the \
             largest number"
        )));
    }
    let (name, name_at) = match params.string("sensor")? {
        None => ("cie1931", None),
        Some((n, p)) => (n, Some(p)),
    };
    let camera_sensor = name != "cie1931";
    if let Some(p) = name_at.filter(|_| camera_sensor) {
        if !CAMERA_SENSORS.contains(&name) {
            return Err(p.error(format!(
                "the sensor \"{}\" is not one pbrt-v4 has (cie1931, {})",
                crate::error::clip_to(name, 60),
                CAMERA_SENSORS.join(", ")
            )));
        }
        warnings.push(p.error(format!(
            "the sensor \"{name}\" is rendered as the cie1931 sensor with its white balance \
             (rayforge has not the camera's response curves)"
        )));
    }
    let (temperature, at) = match params.float_at("whitebalance")? {
        None => (if camera_sensor { 6500.0 } else { 0.0 }, None),
        Some((v, p)) => (if v == 0.0 && camera_sensor { 6500.0 } else { v }, Some(p)),
    };
    let max_component = match params.float_at("maxcomponentvalue")? {
        None => f64::INFINITY,
        Some((v, p)) if v.is_nan() || v <= 0.0 => {
            return Err(p.error(format!(
                "a sample's largest component is capped at a value above 0, found {v}"
            )))
        }
        Some((v, _)) => v,
    };
    if !(temperature >= 0.0 && temperature.is_finite()) {
        let message = format!(
            "a white balance is 0 (none) or a colour temperature above 0 kelvin, found \
             {temperature}"
        );
        return Err(match at {
            Some(p) => p.error(message),
            None => film.error(message),
        });
    }
    cie1931(ratio, temperature, max_component).map_err(|message| match at {
        Some(p) => p.error(message),
        None => film.error(message),
    })
}

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
fn scaled(ratio: f64) -> Sensor {
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
