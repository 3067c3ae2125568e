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
use crate::film_sensor::{cie1931, scaled};
use rayforge::camera::Sensor;

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
