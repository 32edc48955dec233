//! Sets `has_blender` (and the other programs' cfgs) for the add-on check in
//! `tests/pytest.rs`: ignored with a line naming Blender where it is absent,
//! unless `CI` or `ASPERITY_REQUIRE_ALL` is set. See
//! `asperity_fixtures::programs`.

fn main() {
    asperity_fixtures::programs::emit_cfgs();
}
