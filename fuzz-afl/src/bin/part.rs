//! AFL++ entry point for rayforge-fuzz's `part` target: the same function the stable fuzzer
//! and `cargo test -p rayforge-fuzz` run, so a finding here replays there with `--replay`.

fn main() {
    // `nohook`, as the other targets: a panic that escapes the target aborts (a crash for
    // AFL); the stable fuzzer counts any a reader catches itself apart, as "caught panics".
    afl::fuzz_nohook!(|input: &[u8]| {
        rayforge_fuzz::Target::Part.run(input);
    });
}
