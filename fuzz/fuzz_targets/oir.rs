#![no_main]
//! The Olympus `.oir` and packed `.poir` readers (`asperity_io::decode`), as
//! every command reads one: each input is read as both (one target keeps
//! CI's smoke run short; the seeds hold an .oir and a .poir).

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Oir, data);
    read_as(asperity_io::Format::Poir, data);
});
