//! AFL++ entry point for rayforge-fuzz's `gltf` target: the same function the stable fuzzer
//! and `cargo test -p rayforge-fuzz` run, so a finding here replays there with `--replay`.

fn main() {
    // `nohook`: a panic that escapes the target aborts (a crash for AFL), but one the reader
    // catches itself (the glTF crate's) is not, as in the stable fuzzer, which counts those
    // apart as "caught panics".
    afl::fuzz_nohook!(|input: &[u8]| {
        rayforge_fuzz::Target::Gltf.run(input);
    });
}
