//! No code: this crate only asks for dependency features (see its `Cargo.toml`), so that the
//! CLI's and the Python package's builds reuse what the README's test command compiled.
#![deny(missing_docs)]
