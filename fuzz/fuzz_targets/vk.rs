#![no_main]
//! The Keyence VK reader (`asperity_io::decode`; `.vk4` and the zipped
//! `.vk6`), as every command reads one.

include!("common.rs");

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    read_as(asperity_io::Format::Vk, data);
});
