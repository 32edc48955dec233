//! Integration tests of asperity-io: round trips, independent readers, bad input.

mod fixtures;
mod fuzz_regressions;
mod independent;
mod malformed;
mod polygons;
mod python;
mod registry;
mod roundtrip;
