//! Named metals' complex refractive indices `η + iκ` reduced to linear RGB, so that scenes can
//! say "gold" instead of six numbers.
//!
//! Where the numbers come from (measured optical constants are facts; the table is our own):
//! - aluminium, gold, silver, copper: the spectral data of Mitsuba 3's conductor presets as its
//!   RGB mode reduces them (aluminium exactly as the reference scenes give it, the others
//!   rounded to six figures), so renders match Mitsuba's;
//! - chromium, nickel: the same kind of spectral data (Palik's handbook via Mitsuba 0.5's `ior`
//!   files) integrated to linear sRGB as tabulated in Tungsten's `ComplexIorData`;
//! - iron, platinum: measured `n`, `k` at 650, 550 and 450 nm, as tabulated in the Chaos Group
//!   article "Understanding metalness" (2014);
//! - titanium: the Lorentz–Drude fit of Rakić et al. 1998 (Appl. Opt. 37, 5271) evaluated here
//!   at 650, 550 and 450 nm (450 nm lies a little below the fit's 470 nm validity range).

use crate::color::Color;

/// One table row: name, η (red, green, blue), κ (red, green, blue).
type Row = (&'static str, [f64; 3], [f64; 3]);

const TABLE: &[Row] = &[
    (
        "aluminium",
        [1.6575, 0.880405, 0.521244],
        [9.22381, 6.2695, 4.837],
    ),
    (
        "gold",
        [0.143036, 0.375307, 1.44205],
        [3.98300, 2.38556, 1.60336],
    ),
    (
        "silver",
        [0.155276, 0.116728, 0.138388],
        [4.82835, 3.12222, 2.14690],
    ),
    (
        "copper",
        [0.201005, 0.923750, 1.10222],
        [3.91326, 2.45305, 2.14209],
    ),
    (
        "chromium",
        [4.36968, 2.91670, 1.65470],
        [5.20643, 4.23136, 3.75495],
    ),
    (
        "nickel",
        [2.36728, 1.66336, 1.46706],
        [4.49883, 3.05016, 2.34543],
    ),
    ("iron", [2.9114, 2.9497, 2.5845], [3.0893, 2.9318, 2.7670]),
    (
        "platinum",
        [2.3757, 2.0847, 1.8453],
        [4.2655, 3.7153, 3.1365],
    ),
    (
        "titanium",
        [2.0945, 1.7897, 1.3343],
        [3.1986, 3.0017, 2.7597],
    ),
];

/// The names [`metal`] knows, for error messages and documentation.
pub const METAL_NAMES: &[&str] = &[
    "aluminium",
    "gold",
    "silver",
    "copper",
    "chromium",
    "nickel",
    "iron",
    "platinum",
    "titanium",
];

/// The complex index `(η, κ)` of a named metal, per RGB channel; `None` for an unknown name.
/// Accepts the British and American "aluminium"/"aluminum" and the chemical symbols.
pub fn metal(name: &str) -> Option<(Color, Color)> {
    let lower = name.to_ascii_lowercase();
    let canonical = match lower.as_str() {
        "aluminum" | "al" => "aluminium",
        "au" => "gold",
        "ag" => "silver",
        "cu" => "copper",
        "cr" => "chromium",
        "ni" => "nickel",
        "fe" => "iron",
        "pt" => "platinum",
        "ti" => "titanium",
        other => other,
    };
    TABLE
        .iter()
        .find(|(n, _, _)| *n == canonical)
        .map(|(_, eta, k)| {
            (
                Color::new(eta[0], eta[1], eta[2]),
                Color::new(k[0], k[1], k[2]),
            )
        })
}

/// The complex index `(η, κ)` of a conductor that reflects `reflectance` head-on: pbrt-v4's
/// `reflectance` parameter of its `conductor` and `coatedconductor`, turned into an index as
/// pbrt-v4 does (`η = 1`, `κ = 2 √r / √(1 − r)`, which makes the normal-incidence Fresnel
/// reflectance `((η − 1)² + κ²) / ((η + 1)² + κ²)` exactly `r`). Each channel is held in
/// `[0, 0.9999]` first, as pbrt-v4 holds it.
pub fn conductor_for_reflectance(reflectance: Color) -> (Color, Color) {
    let k = |r: f64| {
        let r = if r.is_nan() {
            0.0
        } else {
            r.clamp(0.0, 0.9999)
        };
        2.0 * r.sqrt() / (1.0 - r).sqrt()
    };
    (
        Color::WHITE,
        Color::new(
            k(reflectance.red),
            k(reflectance.green),
            k(reflectance.blue),
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::bsdf::fresnel;

    #[test]
    fn every_listed_name_is_known_and_aluminium_is_exact() {
        assert_eq!(METAL_NAMES.len(), TABLE.len());
        for name in METAL_NAMES {
            let (eta, k) = metal(name).expect(name);
            let f0 = fresnel::conductor_normal(eta, k);
            // Metals reflect much, but not everything, head-on.
            assert!(f0.max_channel() < 1.0 && f0.red > 0.4, "{name}: {f0:?}");
        }
        let (eta, k) = metal("Aluminum").expect("aluminium");
        assert_eq!(eta, Color::new(1.6575, 0.880405, 0.521244));
        assert_eq!(k, Color::new(9.22381, 6.2695, 4.837));
        assert_eq!(metal("Au"), metal("gold"));
        assert!(metal("unobtainium").is_none());
    }

    #[test]
    fn a_reflectance_becomes_an_index_that_reflects_it_head_on() {
        let r = Color::new(0.9, 0.5, 0.02);
        let (eta, k) = conductor_for_reflectance(r);
        let f0 = fresnel::conductor_normal(eta, k);
        assert!((f0 - r).max_channel().abs() < 1e-12, "{f0:?}");
        assert!((fresnel::conductor(1.0, eta, k) - r).max_channel().abs() < 1e-9);
        let (_, k) = conductor_for_reflectance(Color::new(2.0, -1.0, f64::NAN));
        assert!(k.to_array().iter().all(|x| x.is_finite()), "{k:?}");
    }

    #[test]
    fn gold_and_copper_are_warm_and_silver_is_neutral() {
        for warm in ["gold", "copper"] {
            let (eta, k) = metal(warm).expect(warm);
            let f0 = fresnel::conductor_normal(eta, k);
            assert!(f0.red > f0.green && f0.green > f0.blue, "{warm}: {f0:?}");
        }
        let (eta, k) = metal("silver").expect("silver");
        let f0 = fresnel::conductor_normal(eta, k);
        assert!(f0.red > 0.9 && f0.blue > 0.85, "{f0:?}");
    }
}
