//! pbrt-v4's spectral values turned into the linear sRGB rayforge renders in, as pbrt-v4
//! itself turns them into an RGB film's pixels.
//!
//! - **An `rgb` on a light** is, to pbrt-v4, `RGBIlluminantSpectrum`: a smooth spectrum whose
//!   reflectance gives the rgb, times the colour space's illuminant (D65 for sRGB), with the
//!   light's scale divided by that illuminant's luminance. Its film's sensor (`cie1931`, no
//!   white balance) maps the product back to the same rgb: the rgb is the light's colour.
//! - **A `blackbody` temperature or wavelength–value pairs on a light**: pbrt-v4 divides the
//!   light's scale by the spectrum's luminance, so the light has luminance 1 (times `scale`)
//!   whatever the spectrum's size; its colour is the spectrum's chromaticity in sRGB. The
//!   spectrum is integrated against the CIE 1931 colour matching functions as the renderer's
//!   `shading::spectrum` does (Wyman, Sloan and Shirley's analytic fit, 360 to 830 nm).
//! - **Named spectra**: `stdillum-D65` is sRGB's white; the metals pbrt-v4 names
//!   (`metal-Ag-`, `-Al-`, `-Au-`, `-Cu-eta` and `-k`) are rayforge's own named metals
//!   (`shading::spectrum::pbrt_metal`); the glasses (`glass-BK7`, `-BAF10`, `-FK51A`,
//!   `-LASF9`, `-F5`, `-F10`, `-F11`) are one index each, their Sellmeier index at 550 nm
//!   (`shading::spectrum::glass_index`): rayforge's glass does not disperse. Other names are
//!   refused at the parameter.
//! - **Wavelength–value pairs for an index** (`eta`, `k`): the values at 650, 550 and 450 nm,
//!   the red, green and blue of the metals table.
//! - **A reflectance as wavelength–value pairs**: the spectrum under a 6504 K blackbody (the
//!   colour temperature of D65) against that light's own colour, channel by channel, so a flat
//!   spectrum of 0.5 is grey 0.5.

use super::params::{Param, ParamType, Values};
use crate::error::SceneError;
use rayforge::shading::spectrum::{
    glass_index, pbrt_metal, planck, spectrum_to_xyz, xyz_to_linear_srgb, GLASS_NAMES,
};
use rayforge::Color;

/// What a spectrum stands for, which decides how it becomes a colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpectrumUse {
    /// Light given off (`L`, `I`).
    Illuminant,
    /// A share of light (a reflectance), 0 to 1.
    Albedo,
    /// A refractive index's real part or extinction coefficient.
    Index,
}

/// The metals pbrt-v4 names that rayforge's table has (`metal-NAME-eta`, `metal-NAME-k`).
const METALS: &[&str] = &["Ag", "Al", "Au", "Cu"];

/// The colour of parameter `p` (of type `rgb`, `spectrum` or `blackbody`) used as `usage`.
pub fn color(p: &Param, usage: SpectrumUse) -> Result<Color, SceneError> {
    match (p.ty, &p.values) {
        (ParamType::Rgb, Values::Numbers(v)) if v.len() == 3 => {
            let c = Color::new(v[0], v[1], v[2]);
            if usage == SpectrumUse::Albedo && c.red.min(c.green).min(c.blue) < 0.0 {
                return Err(p.error("a reflectance is not negative"));
            }
            Ok(c)
        }
        (ParamType::Rgb, _) => Err(p.error("takes one colour: three numbers")),
        (ParamType::Blackbody, Values::Numbers(v)) if v.len() == 1 => {
            if v[0] <= 0.0 {
                return Err(p.error("a blackbody's temperature is above 0 kelvin"));
            }
            let xyz = spectrum_to_xyz(|l| planck(l, v[0]));
            match usage {
                SpectrumUse::Illuminant => Ok(rgb_of_unit_luminance(xyz)),
                _ => Err(p.error("a blackbody is a light's colour, not a surface's")),
            }
        }
        (ParamType::Blackbody, _) => Err(p.error("takes one temperature, in kelvin")),
        (ParamType::Spectrum, Values::Strings(names)) if names.len() == 1 => {
            named(p, &names[0], usage)
        }
        (ParamType::Spectrum, Values::Numbers(v)) if v.len() >= 2 => pairs(p, v, usage),
        _ => Err(p.error(
            "takes an rgb colour, a spectrum (a name or wavelength–value pairs) or a \
             blackbody temperature",
        )),
    }
}

/// A named spectrum as `usage`.
fn named(p: &Param, name: &str, usage: SpectrumUse) -> Result<Color, SceneError> {
    if usage == SpectrumUse::Illuminant && name == "stdillum-D65" {
        return Ok(Color::WHITE);
    }
    if usage == SpectrumUse::Index {
        if let Some(eta) = glass_index(name) {
            return Ok(Color::new(eta, eta, eta));
        }
        let metal = pbrt_metal(name).and_then(|(eta, k)| {
            if name.ends_with("-eta") {
                Some(eta)
            } else if name.ends_with("-k") {
                Some(k)
            } else {
                None
            }
        });
        if let Some(c) = metal {
            return Ok(c);
        }
    }
    if name.contains('.') {
        return Err(p.error(format!(
            "spectra from files (\"{name}\") are not read: give an rgb colour or one of the \
             named spectra"
        )));
    }
    let known = match usage {
        SpectrumUse::Illuminant => "stdillum-D65".to_string(),
        SpectrumUse::Index => {
            let mut names: Vec<String> = GLASS_NAMES.iter().map(|n| n.to_string()).collect();
            for m in METALS {
                names.push(format!("metal-{m}-eta"));
                names.push(format!("metal-{m}-k"));
            }
            names.join(", ")
        }
        SpectrumUse::Albedo => "none".to_string(),
    };
    Err(p.error(format!(
        "the named spectrum \"{}\" is not one rayforge reads here; it reads: {known}",
        crate::error::clip_to(name, 60)
    )))
}

/// Wavelength–value pairs as `usage`.
fn pairs(p: &Param, v: &[f64], usage: SpectrumUse) -> Result<Color, SceneError> {
    let points: Vec<(f64, f64)> = v.chunks_exact(2).map(|c| (c[0], c[1])).collect();
    if points.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(p.error("a spectrum's wavelengths rise from pair to pair"));
    }
    let at = |l: f64| piecewise(&points, l);
    match usage {
        SpectrumUse::Index => Ok(Color::new(at(650.0), at(550.0), at(450.0))),
        SpectrumUse::Illuminant => {
            let xyz = spectrum_to_xyz(at);
            if xyz[1] <= 0.0 || xyz[1].is_nan() {
                return Err(p.error("this light's spectrum gives no visible light"));
            }
            Ok(rgb_of_unit_luminance(xyz))
        }
        SpectrumUse::Albedo => {
            let lit = xyz_to_linear_srgb(spectrum_to_xyz(|l| at(l) * planck(l, 6504.0)));
            let white = xyz_to_linear_srgb(spectrum_to_xyz(|l| planck(l, 6504.0)));
            let c = Color::new(
                lit.red / white.red,
                lit.green / white.green,
                lit.blue / white.blue,
            );
            Ok(Color::new(
                c.red.max(0.0),
                c.green.max(0.0),
                c.blue.max(0.0),
            ))
        }
    }
}

/// The piecewise-linear spectrum through `points` at `l` (constant past its ends).
fn piecewise(points: &[(f64, f64)], l: f64) -> f64 {
    let first = points[0];
    let last = points[points.len() - 1];
    if l <= first.0 {
        return first.1;
    }
    if l >= last.0 {
        return last.1;
    }
    let i = points.partition_point(|p| p.0 <= l);
    let (a, b) = (points[i - 1], points[i]);
    a.1 + (b.1 - a.1) * (l - a.0) / (b.0 - a.0)
}

/// The linear sRGB colour of luminance 1 with the chromaticity of `xyz`.
fn rgb_of_unit_luminance(xyz: [f64; 3]) -> Color {
    let y = xyz[1].max(1e-300);
    let c = xyz_to_linear_srgb([xyz[0] / y, 1.0, xyz[2] / y]);
    // Chromaticities outside sRGB's gamut (a deep red blackbody) lose what sRGB cannot show.
    Color::new(c.red.max(0.0), c.green.max(0.0), c.blue.max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::params::{parse, Params};
    use crate::pbrt::stream::Stream;
    use std::path::Path;
    use std::rc::Rc;

    fn colour(decl: &str, usage: SpectrumUse) -> Result<Color, SceneError> {
        let mut s = Stream::new(decl, Rc::from(Path::new("s.pbrt")));
        let params = Params::new(
            parse(
                &mut s,
                "Material",
                &crate::pbrt::input::ValueBudget::new(1000),
            )
            .unwrap(),
            &[],
        );
        let p = params
            .find(
                "v",
                &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
            )
            .unwrap();
        color(p, usage)
    }

    #[test]
    fn a_blackbody_at_d65s_temperature_is_near_white_of_luminance_one() {
        let c = colour("\"blackbody v\" 6504", SpectrumUse::Illuminant).unwrap();
        assert!((c.luminance() - 1.0).abs() < 0.02, "{c:?}");
        assert!((c.red - c.blue).abs() < 0.1, "{c:?}");
        let warm = colour("\"blackbody v\" 2700", SpectrumUse::Illuminant).unwrap();
        assert!(warm.red > warm.green && warm.green > warm.blue, "{warm:?}");
    }

    #[test]
    fn a_flat_reflectance_is_grey_and_pairs_are_read_between_their_points() {
        let c = colour("\"spectrum v\" [300 0.5 800 0.5]", SpectrumUse::Albedo).unwrap();
        for channel in [c.red, c.green, c.blue] {
            assert!((channel - 0.5).abs() < 1e-9, "{c:?}");
        }
        let eta = colour("\"spectrum v\" [400 1 700 2]", SpectrumUse::Index).unwrap();
        assert!((eta.red - 1.0 - 250.0 / 300.0).abs() < 1e-12);
        assert!(colour("\"spectrum v\" [500 1 400 2]", SpectrumUse::Index).is_err());
    }

    #[test]
    fn named_spectra() {
        let cu = colour("\"spectrum v\" \"metal-Cu-eta\"", SpectrumUse::Index).unwrap();
        let (eta, _) = rayforge::shading::bsdf::metal("copper").unwrap();
        assert_eq!(cu, eta);
        let bk7 = colour("\"spectrum v\" \"glass-BK7\"", SpectrumUse::Index).unwrap();
        assert_eq!(Some(bk7.red), glass_index("glass-BK7"));
        let white = colour("\"spectrum v\" \"stdillum-D65\"", SpectrumUse::Illuminant).unwrap();
        assert_eq!(white, Color::WHITE);
        let err = colour("\"spectrum v\" \"metal-CuZn-eta\"", SpectrumUse::Index).unwrap_err();
        assert!(err.message.contains("metal-CuZn-eta"), "{err}");
        assert!(err.message.contains("glass-BK7"), "{err}");
        let rgb = colour("\"rgb v\" [0.1 0.2 0.3]", SpectrumUse::Illuminant).unwrap();
        assert_eq!(rgb, Color::new(0.1, 0.2, 0.3));
    }
}
