//! Integration tests of asperity-io: round trips, independent readers, bad input.

mod fixtures;
mod independent;
mod malformed;
mod python;
mod roundtrip;
