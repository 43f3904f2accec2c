//! The packaged FMUs (`target/fmu/2.0/*.fmu` and `target/fmu/3.0/*.fmu`, written by
//! `cargo run --release -p fmu-build`): what each archive holds and exports (`archive`),
//! the FMUs imported with the `fmi` crate against the library they wrap (`import`), the
//! portable binary's glibc needs and its outputs against the host build (`portable`),
//! the SSP system files and fmucontainer link lists around them (`ssp`), and where they
//! are written (`layout`). One test binary, so the suite links once.

mod archive;
mod import;
mod layout;
mod portable;
mod ssp;
mod value_reference;
