#!/usr/bin/env bash
# Debian packages of the foreign FMU binaries (win64, aarch64 Linux) and of the tests
# that run them here (docs/cross-platform.md):
# - rustc-web, cargo-web, rust-web-src (bookworm-security, Rust 1.96): a compiler whose
#   sysroot is /usr with the standard library's sources at /usr/lib/rustlib/src/rust, so
#   `cargo -Zbuild-std=std` builds std for targets whose prebuilt std rustup cannot
#   download on these machines;
# - gcc-mingw-w64-x86-64: the Windows linker (and the C driver's compiler for Windows);
# - gcc-aarch64-linux-gnu, libc6-dev-arm64-cross: the aarch64 C driver and the sysroot
#   qemu loads it with (the FMU binary itself is linked by zig for glibc 2.17);
# - wine64, qemu-user-static: run the Windows DLL and the aarch64 binary in the tests.
# Installs only what is missing (no network when everything is there).
set -euo pipefail
bash "$(dirname "${BASH_SOURCE[0]}")/apt-install.sh" rustc-web cargo-web rust-web-src \
  gcc-mingw-w64-x86-64 gcc-aarch64-linux-gnu libc6-dev-arm64-cross wine64 qemu-user-static
