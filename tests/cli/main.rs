//! The `stickslip` command line contract, and `import-network`.

mod contract;
mod import;
