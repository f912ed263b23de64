//! Fuzzes the bvh reader: any bytes parse or give an error; none panics, aborts or hangs.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = prehensile_testkit::fuzz_entry::run("bvh", data);
});
