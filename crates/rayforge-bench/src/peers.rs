//! Finding the peers that `bench/peers/setup.sh` installed: each is a file in the peers
//! directory, so a run with an empty directory compares with nobody and says how to fix that.

use std::path::{Path, PathBuf};

/// The command that installs every peer, quoted in every "skipped" note.
pub const SETUP: &str = "bench/peers/setup.sh [RAYTRACER_RS_CHECKOUT]";

/// How to get Don Cross's program: setup.sh builds it from this repository when given one.
const CROSS_SETUP: &str = "CROSS_RAYTRACE=CHECKOUT_OF_cosinekitty/raytrace bench/peers/setup.sh";

/// The peers found (a path for each that is there).
#[derive(Debug, Clone, Default)]
pub struct Peers {
    /// Our Embree harness, `embree_primary`.
    pub embree: Option<PathBuf>,
    /// POV-Ray 3.7 (setup.sh links Debian's `povray` here).
    pub povray: Option<PathBuf>,
    /// raytracer_rs's cover example, built by setup.sh.
    pub raytracer_rs_cover: Option<PathBuf>,
    /// raytracer_rs's dragons example, built and patched by setup.sh.
    pub raytracer_rs_dragons: Option<PathBuf>,
    /// Don Cross's program (cosinekitty/raytrace), built unmodified by setup.sh.
    pub cross: Option<PathBuf>,
    /// Our llvmpipe harness, `llvmpipe_frame` (OSMesa), built by setup.sh.
    pub llvmpipe: Option<PathBuf>,
}

impl Peers {
    /// Looks for each peer's file in `dir`. Paths are made absolute (links resolved), since
    /// POV-Ray runs in the output directory.
    pub fn find(dir: &Path) -> Self {
        let at = |name: &str| {
            let path = dir.join(name);
            path.is_file().then(|| path.canonicalize().unwrap_or(path))
        };
        Self {
            embree: at("embree_primary"),
            povray: at("povray"),
            raytracer_rs_cover: at("raytracer_rs-cover"),
            raytracer_rs_dragons: at("raytracer_rs-dragons"),
            cross: at("cross-raytrace"),
            llvmpipe: at("llvmpipe_frame"),
        }
    }

    /// One line per peer: where it is, or that it is missing.
    pub fn describe(&self) -> Vec<String> {
        let line = |name: &str, path: &Option<PathBuf>| match path {
            Some(p) => format!("{name}: {}", p.display()),
            None => format!("{name}: not installed ({})", skipped_hint(name)),
        };
        vec![
            line("Embree harness", &self.embree),
            line("POV-Ray", &self.povray),
            line("raytracer_rs cover", &self.raytracer_rs_cover),
            line("raytracer_rs dragons", &self.raytracer_rs_dragons),
            line("Don Cross's program", &self.cross),
            line("llvmpipe harness", &self.llvmpipe),
        ]
    }
}

/// How to get a missing peer.
pub fn skipped_hint(peer: &str) -> String {
    if peer.starts_with("Don Cross") || peer == "cross" {
        format!("run `{CROSS_SETUP}`")
    } else if peer.starts_with("raytracer_rs") {
        format!("run `{SETUP}` with a checkout of richard-dennehy/raytracer_rs")
    } else {
        format!("run `{SETUP}`")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_directory_has_no_peers_and_says_how_to_get_them() {
        let dir = tempfile::tempdir().unwrap();
        let peers = Peers::find(dir.path());
        assert!(peers.embree.is_none() && peers.povray.is_none());
        assert!(peers.describe().iter().all(|l| l.contains("setup.sh")));
    }
}
