//! Sets `has_blender`, `has_gwyddion`, `has_chromium`, `has_node` and `has_xvfb` for the
//! real-program checks (`tests/real_programs.rs`): a check whose program is
//! absent is ignored with a line naming it, unless `CI` or
//! `ASPERITY_REQUIRE_ALL` is set (then it runs and fails). See
//! `asperity_fixtures::programs`.

fn main() {
    asperity_fixtures::programs::emit_cfgs();
}
