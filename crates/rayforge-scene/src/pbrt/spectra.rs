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
//!   spectrum is integrated here against Wyman, Sloan and Shirley's analytic fit of the CIE
//!   1931 colour matching functions (2013), every nanometre from 360 to 830 nm.
//! - **Named spectra**: `stdillum-D65` is sRGB's white; the metals pbrt-v4 names
//!   (`metal-Ag-`, `-Al-`, `-Au-`, `-Cu-eta` and `-k`) are rayforge's own named metals
//!   (`shading::bsdf::metals`); the glasses (`glass-BK7`, `-BAF10`, `-FK51A`, `-LASF9`, `-F5`,
//!   `-F10`, `-F11`, the Schott glasses BK7, BAF10, FK51A, LASF9, SF5, SF10, SF11) are one
//!   index, the catalogue's at the helium d line (587.6 nm): rayforge's glass does not
//!   disperse. Other names are refused at the parameter.
//! - **Wavelength–value pairs for an index** (`eta`, `k`): the values at 650, 550 and 450 nm,
//!   the red, green and blue of the metals table.
//! - **A reflectance as wavelength–value pairs**: the spectrum under a 6504 K blackbody (the
//!   colour temperature of D65) against that light's own colour, channel by channel, so a flat
//!   spectrum of 0.5 is grey 0.5.

use super::params::{Param, ParamType, Values};
use crate::error::SceneError;
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

/// The named glasses and their indices at 587.6 nm (Schott's catalogue values).
const GLASSES: &[(&str, f64)] = &[
    ("glass-BK7", 1.5168),
    ("glass-BAF10", 1.6700),
    ("glass-FK51A", 1.4866),
    ("glass-LASF9", 1.8503),
    ("glass-F5", 1.6727),
    ("glass-F10", 1.7283),
    ("glass-F11", 1.7847),
];

/// pbrt-v4's metal names and rayforge's for the same metal.
const METALS: &[(&str, &str)] = &[
    ("Ag", "silver"),
    ("Al", "aluminium"),
    ("Au", "gold"),
    ("Cu", "copper"),
];

/// The index a named glass has, for a dielectric's `"spectrum eta"`.
pub fn glass_index(name: &str) -> Option<f64> {
    GLASSES.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
}

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
            let xyz = xyz_of(|l| planck(l, v[0]));
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
        let metal = name
            .strip_prefix("metal-")
            .and_then(|rest| rest.rsplit_once('-'))
            .and_then(|(metal, part)| {
                let ours = METALS.iter().find(|(m, _)| *m == metal)?.1;
                let (eta, k) = rayforge::shading::bsdf::metal(ours)?;
                match part {
                    "eta" => Some(eta),
                    "k" => Some(k),
                    _ => None,
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
            let mut names: Vec<String> = GLASSES.iter().map(|(n, _)| n.to_string()).collect();
            for (m, _) in METALS {
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
            let xyz = xyz_of(at);
            if xyz[1] <= 0.0 || xyz[1].is_nan() {
                return Err(p.error("this light's spectrum gives no visible light"));
            }
            Ok(rgb_of_unit_luminance(xyz))
        }
        SpectrumUse::Albedo => {
            let lit = xyz_to_rgb(xyz_of(|l| at(l) * planck(l, 6504.0)));
            let white = xyz_to_rgb(xyz_of(|l| planck(l, 6504.0)));
            let c = Color::new(lit[0] / white[0], lit[1] / white[1], lit[2] / white[2]);
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

/// Planck's law: the spectral radiance of a blackbody at `kelvin`, at `nm` nanometres (in
/// arbitrary units: only its shape matters here).
fn planck(nm: f64, kelvin: f64) -> f64 {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = nm * 1e-9;
    2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * kelvin)).exp_m1())) * 1e-12
}

/// One lobe of the fit: a Gaussian of different widths on its two sides.
fn lobe(l: f64, mean: f64, below: f64, above: f64) -> f64 {
    let s = if l < mean { below } else { above };
    let t = (l - mean) / s;
    (-0.5 * t * t).exp()
}

/// The CIE 1931 colour matching functions at `l` nm, by the multi-lobe fit of Wyman, Sloan
/// and Shirley (2013).
fn matching(l: f64) -> [f64; 3] {
    let x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7)
        - 0.065 * lobe(l, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
    [x, y, z]
}

/// The XYZ of the spectrum `s` (unnormalised sums over every nanometre).
fn xyz_of(s: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    for nm in 360..=830 {
        let l = f64::from(nm);
        let v = s(l);
        let m = matching(l);
        for c in 0..3 {
            xyz[c] += v * m[c];
        }
    }
    xyz
}

/// Linear sRGB from XYZ (D65 white).
fn xyz_to_rgb([x, y, z]: [f64; 3]) -> [f64; 3] {
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266_0 * x + 1.876_010_8 * y + 0.041_556_0 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

/// The linear sRGB colour of luminance 1 with the chromaticity of `xyz`.
fn rgb_of_unit_luminance(xyz: [f64; 3]) -> Color {
    let y = xyz[1].max(1e-300);
    let [r, g, b] = xyz_to_rgb([xyz[0] / y, 1.0, xyz[2] / y]);
    // Chromaticities outside sRGB's gamut (a deep red blackbody) lose what sRGB cannot show.
    Color::new(r.max(0.0), g.max(0.0), b.max(0.0))
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
        let params = Params::new(parse(&mut s, "Material").unwrap(), &[]);
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
        assert_eq!(bk7.red, 1.5168);
        let white = colour("\"spectrum v\" \"stdillum-D65\"", SpectrumUse::Illuminant).unwrap();
        assert_eq!(white, Color::WHITE);
        let err = colour("\"spectrum v\" \"metal-CuZn-eta\"", SpectrumUse::Index).unwrap_err();
        assert!(err.message.contains("metal-CuZn-eta"), "{err}");
        assert!(err.message.contains("glass-BK7"), "{err}");
        let rgb = colour("\"rgb v\" [0.1 0.2 0.3]", SpectrumUse::Illuminant).unwrap();
        assert_eq!(rgb, Color::new(0.1, 0.2, 0.3));
    }
}
