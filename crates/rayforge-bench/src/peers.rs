//! Finding the peers: each is a file in the peers directory (`--peers`, where
//! `bench/peers/setup.sh` puts Debian's POV-Ray and our harnesses of Embree and Mesa), or a
//! binary named with `--peer NAME=FILE`, which wins over the directory. This repository builds
//! no other project's program: a peer that is neither Debian's nor ours (raytracer_rs, Don
//! Cross's program) is timed only when the user names a binary they built themselves. A peer
//! that is missing is a skipped row that says how to get it.

use std::path::{Path, PathBuf};

/// The command that installs Debian's peers and builds our harnesses.
const SETUP: &str = "bench/peers/setup.sh";

/// Every peer the bench can time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Peer {
    /// Our Embree harness (`bench/peers/embree/primary.c`).
    Embree,
    /// POV-Ray 3.7, Debian's `povray`.
    PovRay,
    /// Our llvmpipe harness (`bench/peers/llvmpipe/frame.c`, Mesa's OSMesa).
    Llvmpipe,
    /// A raytracer_rs binary that renders `cover.yml` at 1080×1080, one sample per pixel.
    RaytracerRsCover,
    /// A raytracer_rs binary that renders `bounding-boxes.yml` at 1920×1080 with its
    /// `Samples::grid(4)`.
    RaytracerRsDragons,
    /// Don Cross's program (cosinekitty/raytrace), its commands `test`, `spheroid`, `block`,
    /// `chessboard` and `kaleid`.
    Cross,
}

impl Peer {
    /// Every peer, in the order the report lists them.
    pub const ALL: [Peer; 6] = [
        Peer::Embree,
        Peer::PovRay,
        Peer::RaytracerRsCover,
        Peer::RaytracerRsDragons,
        Peer::Cross,
        Peer::Llvmpipe,
    ];

    /// The peer's file in the peers directory, and its NAME in `--peer NAME=FILE`.
    pub fn file_name(self) -> &'static str {
        match self {
            Peer::Embree => "embree_primary",
            Peer::PovRay => "povray",
            Peer::Llvmpipe => "llvmpipe_frame",
            Peer::RaytracerRsCover => "raytracer_rs-cover",
            Peer::RaytracerRsDragons => "raytracer_rs-dragons",
            Peer::Cross => "cross-raytrace",
        }
    }

    /// The peer's name in the report.
    fn label(self) -> &'static str {
        match self {
            Peer::Embree => "Embree harness",
            Peer::PovRay => "POV-Ray",
            Peer::Llvmpipe => "llvmpipe harness",
            Peer::RaytracerRsCover => "raytracer_rs cover",
            Peer::RaytracerRsDragons => "raytracer_rs dragons",
            Peer::Cross => "Don Cross's program",
        }
    }

    /// The peer whose file name is `name`.
    fn from_file_name(name: &str) -> Option<Peer> {
        Peer::ALL.into_iter().find(|p| p.file_name() == name)
    }

    /// How to get the peer when it is missing.
    pub fn skipped_hint(self) -> String {
        match self {
            Peer::Embree | Peer::PovRay | Peer::Llvmpipe => {
                format!("run `{SETUP}`, or give `--peer {}=FILE`", self.file_name())
            }
            Peer::RaytracerRsCover | Peer::RaytracerRsDragons | Peer::Cross => format!(
                "give `--peer {}=FILE`, a binary you built (this repository builds no \
                 other project's program; see docs/performance.md)",
                self.file_name()
            ),
        }
    }
}

/// One `--peer NAME=FILE`: a peer's binary named on the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PeerBinary {
    /// Which peer.
    pub peer: Peer,
    /// Its binary.
    pub path: PathBuf,
}

/// Reads `NAME=FILE` for `--peer`; the refusal lists the names.
pub fn parse_peer_binary(text: &str) -> Result<PeerBinary, String> {
    let names = || {
        Peer::ALL
            .iter()
            .map(|p| p.file_name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let Some((name, path)) = text.split_once('=') else {
        return Err(format!("expected NAME=FILE, NAME one of {}", names()));
    };
    let Some(peer) = Peer::from_file_name(name) else {
        return Err(format!(
            "unknown peer `{name}`, expected one of {}",
            names()
        ));
    };
    if path.is_empty() {
        return Err(format!("no FILE after `{name}=`"));
    }
    Ok(PeerBinary {
        peer,
        path: PathBuf::from(path),
    })
}

/// The peers found (a path for each that is there).
#[derive(Debug, Clone, Default)]
pub struct Peers {
    /// Our Embree harness, `embree_primary`.
    pub embree: Option<PathBuf>,
    /// POV-Ray 3.7 (setup.sh links Debian's `povray` here).
    pub povray: Option<PathBuf>,
    /// A raytracer_rs binary rendering the cover.
    pub raytracer_rs_cover: Option<PathBuf>,
    /// A raytracer_rs binary rendering the six dragons at 1920×1080.
    pub raytracer_rs_dragons: Option<PathBuf>,
    /// Don Cross's program (cosinekitty/raytrace).
    pub cross: Option<PathBuf>,
    /// Our llvmpipe harness, `llvmpipe_frame` (OSMesa), built by setup.sh.
    pub llvmpipe: Option<PathBuf>,
}

impl Peers {
    /// Looks for each peer among `given` (`--peer`), then as its file in `dir`. Paths are made
    /// absolute (links resolved), since POV-Ray runs in the output directory.
    pub fn find(dir: &Path, given: &[PeerBinary]) -> Self {
        let at = |peer: Peer| {
            let path = given
                .iter()
                .rev()
                .find(|g| g.peer == peer)
                .map(|g| g.path.clone())
                .unwrap_or_else(|| dir.join(peer.file_name()));
            path.is_file().then(|| path.canonicalize().unwrap_or(path))
        };
        Self {
            embree: at(Peer::Embree),
            povray: at(Peer::PovRay),
            raytracer_rs_cover: at(Peer::RaytracerRsCover),
            raytracer_rs_dragons: at(Peer::RaytracerRsDragons),
            cross: at(Peer::Cross),
            llvmpipe: at(Peer::Llvmpipe),
        }
    }

    /// The path found for `peer`.
    fn get(&self, peer: Peer) -> &Option<PathBuf> {
        match peer {
            Peer::Embree => &self.embree,
            Peer::PovRay => &self.povray,
            Peer::Llvmpipe => &self.llvmpipe,
            Peer::RaytracerRsCover => &self.raytracer_rs_cover,
            Peer::RaytracerRsDragons => &self.raytracer_rs_dragons,
            Peer::Cross => &self.cross,
        }
    }

    /// One line per peer: where it is, or that it is missing and how to get it.
    pub fn describe(&self) -> Vec<String> {
        Peer::ALL
            .into_iter()
            .map(|peer| match self.get(peer) {
                Some(p) => format!("{}: {}", peer.label(), p.display()),
                None => format!("{}: not installed ({})", peer.label(), peer.skipped_hint()),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_directory_has_no_peers_and_says_how_to_get_them() {
        let dir = tempfile::tempdir().unwrap();
        let peers = Peers::find(dir.path(), &[]);
        assert!(peers.embree.is_none() && peers.povray.is_none() && peers.cross.is_none());
        let lines = peers.describe();
        assert_eq!(lines.len(), Peer::ALL.len());
        for line in &lines {
            assert!(line.contains("not installed"), "{line}");
            assert!(line.contains("--peer "), "{line}");
        }
        // Debian's peers and our harnesses come from setup.sh; the others never do.
        for (line, peer) in lines.iter().zip(Peer::ALL) {
            let from_setup = matches!(peer, Peer::Embree | Peer::PovRay | Peer::Llvmpipe);
            assert_eq!(line.contains("setup.sh"), from_setup, "{line}");
        }
    }

    #[test]
    fn a_named_binary_is_found_and_wins_over_the_directory() {
        let dir = tempfile::tempdir().unwrap();
        let in_dir = dir.path().join("povray");
        std::fs::write(&in_dir, "").unwrap();
        let elsewhere = dir.path().join("my-raytrace");
        std::fs::write(&elsewhere, "").unwrap();
        let other_povray = dir.path().join("my-povray");
        std::fs::write(&other_povray, "").unwrap();
        let given = [
            parse_peer_binary(&format!("cross-raytrace={}", elsewhere.display())).unwrap(),
            parse_peer_binary(&format!("povray={}", other_povray.display())).unwrap(),
        ];
        let peers = Peers::find(dir.path(), &given);
        assert_eq!(peers.cross, Some(elsewhere.canonicalize().unwrap()));
        assert_eq!(peers.povray, Some(other_povray.canonicalize().unwrap()));
        // Without --peer, the directory's file counts.
        let peers = Peers::find(dir.path(), &[]);
        assert_eq!(peers.povray, Some(in_dir.canonicalize().unwrap()));
        assert!(peers.cross.is_none());
    }

    #[test]
    fn peer_arguments_are_checked() {
        let ok = parse_peer_binary("raytracer_rs-dragons=/opt/dragons").unwrap();
        assert_eq!(ok.peer, Peer::RaytracerRsDragons);
        assert_eq!(ok.path, PathBuf::from("/opt/dragons"));
        assert!(parse_peer_binary("cross-raytrace")
            .unwrap_err()
            .contains("NAME=FILE"));
        let unknown = parse_peer_binary("mitsuba=/x").unwrap_err();
        assert!(
            unknown.contains("`mitsuba`") && unknown.contains("cross-raytrace"),
            "{unknown}"
        );
        assert!(parse_peer_binary("povray=").unwrap_err().contains("FILE"));
    }
}
