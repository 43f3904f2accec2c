//! The packaged FMUs (`target/fmu/*.fmu`, written by `cargo run --release -p fmu-build`):
//! what each archive holds and exports (`archive`), the FMUs imported with the `fmi`
//! crate against the library they wrap (`import`), the portable binary's glibc needs and
//! its outputs against the host build (`portable`), and the SSP system files and
//! fmucontainer link lists around them (`ssp`). One test binary, so the suite links once.

mod archive;
mod import;
mod portable;
mod ssp;
