//! Test scaffolding shared by Prehensile's crates, kept out of the libraries' public API: a
//! global allocator that counts allocations (for the tests that keep hot loops from allocating)
//! and one entry point per file reader (for the fuzz targets and the corpus replay test).
//! A dev-dependency only; nothing here is meant for users.
#![deny(missing_docs)]

pub mod allocation_count;
pub mod fuzz_entry;
