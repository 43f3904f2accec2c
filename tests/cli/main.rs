//! The `stickslip` command line contract.

mod contract;
