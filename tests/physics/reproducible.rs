//! The same bits on every x86_64 CPU: the paper scene to 0.7 s (breakaway and the first
//! slip) at each fidelity, under each law and inference mode, hashed over every bit of
//! every sample, natively, with glibc's AVX2 and FMA kernels switched off
//! (`GLIBC_TUNABLES`), and on an emulated CPU without AVX and FMA
//! (`qemu-x86_64-static -cpu Nehalem`, package qemu-user-static from
//! scripts/system-deps.sh). The two foreign runs re-run this test binary with
//! [`CHILD`] set, which prints the hashes instead of comparing them.
//!
//! No tolerance: the claim is bit-identity (issue 25), and a last-bit difference grows
//! after breakaway, so anything short of equal hashes fails.

use std::collections::BTreeMap;
use std::process::Command;

use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::neural::inference::Inference;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::simulation::Simulator;
use stickslip_tests::law_of;

/// Set in a child run: print `HASH <case> <hex>` lines and the CPU's features.
const CHILD: &str = "STICKSLIP_REPRODUCIBLE_CHILD";
/// glibc 2.36's names (Debian 12): `AVX2`, `FMA`; the pre-2.33 `AVX2_Usable` spelling is
/// ignored by it (checked with `ld.so --list-diagnostics`).
const NO_FMA_TUNABLES: &str = "glibc.cpu.hwcaps=-AVX2,-FMA";
const LOADER: &str = "/lib64/ld-linux-x86-64.so.2";

/// FNV-1a over bytes: a fixed, documented 64-bit hash (the standard library's hasher
/// may change between Rust versions).
fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Every case: (name, scene).
fn cases() -> Vec<(String, Scene)> {
    let weights = |name: &str| format!("{}/../weights/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let mut laws: Vec<(String, FrictionLawKind, Option<String>, Inference)> = vec![(
        "analytical".into(),
        FrictionLawKind::Exponential,
        None,
        Inference::Exact,
    )];
    for net in ["plain", "signed"] {
        for inference in [Inference::Exact, Inference::F32, Inference::Table] {
            laws.push((
                format!("neural-{net}/{}", inference.name()),
                FrictionLawKind::Neural,
                Some(weights(&format!("paper-{net}"))),
                inference,
            ));
        }
    }
    let mut cases = Vec::new();
    for level in [
        FidelityLevel::Modal,
        FidelityLevel::Beam,
        FidelityLevel::PlaneStress,
    ] {
        for (name, law, weights, inference) in &laws {
            let mut scene = Scene::default();
            scene.fidelity.level = level;
            scene.friction.law = *law;
            scene.friction.weights = weights.clone();
            scene.friction.inference = *inference;
            scene.time.end = 0.7;
            cases.push((format!("{}/{name}", level.name()), scene));
        }
    }
    cases
}

/// The hash of every bit of every sample of a case's run.
fn run_hash(scene: &Scene) -> u64 {
    let checked = scene.clone().check().expect("a valid scene");
    let law = law_of(scene).law().expect("the law");
    let mut sim = Simulator::new(checked, law).expect("the simulator");
    let samples = sim.run(1).expect("the run");
    assert!(
        samples.iter().any(|s| !s.stick),
        "0.7 s of the paper scene reaches the first slip"
    );
    samples.iter().fold(0xcbf2_9ce4_8422_2325, |h, s| {
        let bits = [
            s.time,
            s.tip_deflection,
            s.tip_velocity,
            s.relative_velocity,
            s.friction_force,
            s.holding_force,
            f64::from(u8::from(s.stick)),
        ];
        bits.iter()
            .fold(h, |h, x| fnv1a(h, &x.to_bits().to_le_bytes()))
    })
}

fn hashes() -> BTreeMap<String, u64> {
    cases()
        .iter()
        .map(|(name, scene)| (name.clone(), run_hash(scene)))
        .collect()
}

/// Starts this test in a child process (`wrapper` before the binary, `env` set); the
/// children run while the parent computes its own hashes.
fn spawn(wrapper: &[&str], env: &[(&str, &str)]) -> (String, std::process::Child) {
    let exe = std::env::current_exe().expect("the test binary");
    let mut command = match wrapper.split_first() {
        Some((program, args)) => {
            let mut c = Command::new(program);
            c.args(args).arg(&exe);
            c
        }
        None => Command::new(&exe),
    };
    command
        .args([
            "--exact",
            "reproducible::same_bits_with_and_without_fma",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(CHILD, "1")
        .envs(env.iter().copied())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped());
    let child = command.spawn().expect("start the child");
    (format!("{wrapper:?} {env:?}"), child)
}

/// A child's hashes and whether it saw FMA.
fn finish((what, child): (String, std::process::Child)) -> (BTreeMap<String, u64>, bool) {
    let out = child.wait_with_output().expect("run the child");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "child {what} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut hashes = BTreeMap::new();
    let mut fma = None;
    for line in stdout.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["HASH", name, hex] => {
                hashes.insert(name.to_string(), u64::from_str_radix(hex, 16).unwrap());
            }
            ["FMA", yes] => fma = Some(*yes == "true"),
            _ => {}
        }
    }
    (hashes, fma.expect("the child reports its CPU"))
}

fn cpu_has_fma() -> bool {
    std::arch::is_x86_feature_detected!("fma") && std::arch::is_x86_feature_detected!("avx2")
}

/// glibc's active hwcaps levels (`dl_hwcaps_subdirs_active`) with these tunables: the
/// proof that the tunable took effect.
fn hwcaps_active(tunables: Option<&str>) -> Option<String> {
    let mut command = Command::new(LOADER);
    command.arg("--list-diagnostics");
    if let Some(t) = tunables {
        command.env("GLIBC_TUNABLES", t);
    }
    let out = command.output().ok()?;
    String::from_utf8_lossy(&out.stdout).lines().find_map(|l| {
        l.strip_prefix("dl_hwcaps_subdirs_active=")
            .map(str::to_string)
    })
}

fn found(program: &str) -> bool {
    Command::new(program).arg("--version").output().is_ok()
}

#[test]
fn same_bits_with_and_without_fma() {
    if std::env::var_os(CHILD).is_some() {
        // A line of its own: the harness's "test ... " line has no newline yet.
        println!("\nFMA {}", cpu_has_fma());
        for (name, hash) in hashes() {
            println!("HASH {name} {hash:016x}");
        }
        return;
    }
    let (with, without) = (hwcaps_active(None), hwcaps_active(Some(NO_FMA_TUNABLES)));
    if with.is_some() && with == without {
        panic!("GLIBC_TUNABLES={NO_FMA_TUNABLES} does not change glibc's hwcaps ({with:?})");
    }
    let qemu = found("qemu-x86_64-static");
    let nehalem = qemu.then(|| spawn(&["qemu-x86_64-static", "-cpu", "Nehalem"], &[]));
    let tuned = spawn(&[], &[("GLIBC_TUNABLES", NO_FMA_TUNABLES)]);
    let native = hashes();
    let mut columns: Vec<(&str, BTreeMap<String, u64>)> = Vec::new();
    columns.push(("glibc -AVX2,-FMA", finish(tuned).0));
    if let Some(nehalem) = nehalem {
        let (nehalem, fma) = finish(nehalem);
        assert!(!fma, "qemu's Nehalem has no FMA");
        columns.push(("qemu Nehalem", nehalem));
    } else {
        eprintln!(
            "\n!!!!!!!! SKIPPED the run without AVX/FMA under qemu: qemu-x86_64-static is \
             not installed (bash scripts/system-deps.sh installs qemu-user-static) !!!!!!!!\n"
        );
    }

    println!(
        "native CPU has AVX2+FMA: {}; glibc hwcaps active {with:?}, with the tunable {without:?}",
        cpu_has_fma()
    );
    print!("{:<36} {:<16}", "case (0.7 s)", "native");
    for (title, _) in &columns {
        print!(" {title:<18}");
    }
    println!();
    let mut differ = Vec::new();
    for (name, hash) in &native {
        print!("{name:<36} {hash:016x}");
        for (title, other) in &columns {
            let same = other.get(name) == Some(hash);
            print!(" {:<18}", if same { "same" } else { "DIFFERENT" });
            if !same {
                differ.push(format!("{name} ({title})"));
            }
        }
        println!();
    }
    assert!(differ.is_empty(), "not the same bits: {differ:?}");
}
