//! AFL++ entry point for rayforge-fuzz's `ply` target: the same function the stable fuzzer
//! and `cargo test -p rayforge-fuzz` run, so a finding here replays there with `--replay`.

fn main() {
    // `nohook`: a panic that escapes the target aborts (a crash for AFL), as in the other
    // entry points.
    afl::fuzz_nohook!(|input: &[u8]| {
        rayforge_fuzz::Target::Ply.run(input);
    });
}
