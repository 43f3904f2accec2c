//! Through the C ABI:
//! - many instances in many threads, interleaved, give the outputs of one instance alone,
//!   bit for bit; so does a run after fmi2Reset;
//! - resource locations: odd characters in the path (percent-encoded and raw), a missing
//!   folder, unreadable or corrupted weights, non-file URIs and NULL;
//! - `valgrind_driver_loop` (ignored): the loop that `scripts/valgrind.sh` runs under
//!   valgrind.

use std::ffi::{c_char, c_void, CString};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Barrier;
use stickslip::choice::Choice;
use stickslip::scene::{FidelityLevel, FrictionLawKind};
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::ffi2::*;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::FmuKind;

use crate::allocations::live_bytes;
use stickslip_tests::fmi_log::{record, Entry, Log};
use stickslip_tests::vr;

const OK: fmi2Status = 0;
const ERROR: fmi2Status = 3;

// ---------------------------------------------------------------------------------------
// Importer side.

fn logger() -> fmi2CallbackLogger {
    type Fixed = extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        *const c_char,
    );
    // SAFETY: see `record`.
    unsafe { std::mem::transmute::<Fixed, fmi2CallbackLogger>(record) }
}

fn callbacks(log: &Log) -> fmi2CallbackFunctions {
    fmi2CallbackFunctions {
        logger: Some(logger()),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: log as *const Log as *mut c_void,
    }
}

fn weights_dir() -> PathBuf {
    stickslip_tests::weights_dir()
}

/// file:// URI of a folder, every byte outside the unreserved set percent-encoded.
fn file_uri(dir: &Path) -> String {
    use std::os::unix::ffi::OsStrExt;
    let mut uri = String::from("file://");
    for &b in dir.as_os_str().as_bytes() {
        if b.is_ascii_alphanumeric() || b"/-._~".contains(&b) {
            uri.push(b as char);
        } else {
            uri += &format!("%{b:02X}");
        }
    }
    uri
}

/// fmi2Instantiate with resource location `uri` (None: NULL). Returns the instance (NULL
/// when refused) and what was logged.
fn instantiate_at(kind: FmuKind, uri: Option<&str>) -> (fmi2Component, Vec<Entry>) {
    let log = Log::default();
    let functions = callbacks(&log);
    let guid = CString::new(kind.guid()).unwrap();
    let uri = uri.map(|u| CString::new(u).unwrap());
    let c = unsafe {
        fmi2Instantiate(
            c"resources".as_ptr(),
            1,
            guid.as_ptr(),
            uri.as_ref().map_or(null(), |u| u.as_ptr()),
            &functions,
            0,
            0,
        )
    };
    // Instances that were created log nothing at instantiation; freed at once, so the
    // log may go out of scope.
    let entries = log.into_inner().unwrap();
    (c, entries)
}

/// A temporary folder whose path has spaces and non-ASCII characters.
fn odd_temp_dir(tag: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .subsec_nanos();
    std::env::temp_dir().join(format!(
        "stickslip {tag} {} {nanos} Größe ü 漢字",
        std::process::id()
    ))
}

/// A copy of the shipped resources in `<root>/res dir é/resources`.
fn copy_resources(root: &Path) -> PathBuf {
    let dir = root.join("res dir é").join("resources");
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(weights_dir()).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, dir.join(path.file_name().unwrap())).unwrap();
    }
    dir
}

/// The StickSlipBeam value references these tests use, by name.
struct BeamVrs {
    fidelity: u32,
    friction_law: u32,
    weights: u32,
    /// tip_deflection, tip_velocity, relative_velocity, friction_force, holding_force.
    real_outputs: [u32; 5],
    stick: u32,
    transitions: u32,
}

impl BeamVrs {
    fn get() -> Self {
        let vr = vr::<StickSlipBeam>;
        Self {
            fidelity: vr("fidelity.level"),
            friction_law: vr("friction.law"),
            weights: vr("friction.weights"),
            real_outputs: [
                vr("tip_deflection"),
                vr("tip_velocity"),
                vr("relative_velocity"),
                vr("friction_force"),
                vr("holding_force"),
            ],
            stick: vr("stick"),
            transitions: vr("transitions"),
        }
    }
}

const H: f64 = 1e-3;
/// The paper scene runs to 1.2 s.
const STEPS: usize = 1200;

/// One communication point: the five Real outputs, stick and transitions, as bits.
type Point = [u64; 7];

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Config {
    fidelity: FidelityLevel,
    /// friction.law.
    law: FrictionLawKind,
    /// friction.weights for the neural law.
    weights: &'static str,
}

/// The friction laws the instances of one thread use, all on the paper scene.
const LAWS: [(FrictionLawKind, &str); 4] = [
    (FrictionLawKind::Exponential, "paper-plain.json"),
    (FrictionLawKind::Neural, "paper-plain.json"),
    (FrictionLawKind::Coulomb, "paper-plain.json"),
    (FrictionLawKind::Neural, "paper-signed.json"),
];

/// A StickSlipBeam instance on the paper scene (the parameters' start values) from 0 to
/// 1.2 s, stepped one communication step at a time.
struct Run {
    c: fmi2Component,
    log: Box<Log>,
    _functions: Box<fmi2CallbackFunctions>,
    k: usize,
    points: Vec<Point>,
}

impl Run {
    fn start(config: Config, uri: &str) -> Run {
        let log = Box::new(Log::default());
        let functions = Box::new(callbacks(&log));
        let guid = CString::new(FmuKind::StickSlipBeam.guid()).unwrap();
        let uri = CString::new(uri).unwrap();
        let weights = CString::new(config.weights).unwrap();
        let c = unsafe {
            fmi2Instantiate(
                c"beam".as_ptr(),
                1,
                guid.as_ptr(),
                uri.as_ptr(),
                &*functions,
                0,
                0,
            )
        };
        assert!(!c.is_null(), "fmi2Instantiate: {:?}", log);
        let run = Run {
            c,
            log,
            _functions: functions,
            k: 0,
            points: Vec::with_capacity(STEPS),
        };
        let vrs = BeamVrs::get();
        unsafe {
            run.ok(
                fmi2SetInteger(
                    c,
                    [vrs.fidelity, vrs.friction_law].as_ptr(),
                    2,
                    [config.fidelity.code(), config.law.code()].as_ptr(),
                ),
                "fmi2SetInteger",
            );
            run.ok(
                fmi2SetString(c, &vrs.weights, 1, &weights.as_ptr()),
                "fmi2SetString",
            );
        }
        run.initialize();
        run
    }

    fn ok(&self, status: fmi2Status, what: &str) {
        assert_eq!(status, OK, "{what}: {:?}", self.log.lock().unwrap());
    }

    fn initialize(&self) {
        unsafe {
            self.ok(
                fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 1, STEPS as f64 * H),
                "fmi2SetupExperiment",
            );
            self.ok(
                fmi2EnterInitializationMode(self.c),
                "fmi2EnterInitializationMode",
            );
            self.ok(
                fmi2ExitInitializationMode(self.c),
                "fmi2ExitInitializationMode",
            );
        }
    }

    fn step(&mut self) {
        let c = self.c;
        let vrs = BeamVrs::get();
        let mut point = [0u64; 7];
        unsafe {
            self.ok(fmi2DoStep(c, self.k as f64 * H, H, 1), "fmi2DoStep");
            let mut reals = [0.0; 5];
            self.ok(
                fmi2GetReal(c, vrs.real_outputs.as_ptr(), 5, reals.as_mut_ptr()),
                "fmi2GetReal",
            );
            let mut stick = 0;
            self.ok(
                fmi2GetBoolean(c, &vrs.stick, 1, &mut stick),
                "fmi2GetBoolean",
            );
            let mut transitions = 0;
            self.ok(
                fmi2GetInteger(c, &vrs.transitions, 1, &mut transitions),
                "fmi2GetInteger",
            );
            for (slot, r) in point.iter_mut().zip(reals) {
                *slot = r.to_bits();
            }
            point[5] = stick as u64;
            point[6] = transitions as u64;
        }
        self.points.push(point);
        self.k += 1;
    }

    fn run_to_end(&mut self) {
        while self.k < STEPS {
            self.step();
        }
    }

    /// fmi2Reset, then the same parameters again (Reset restores the start values).
    fn reset(&mut self, config: Config) -> Vec<Point> {
        unsafe {
            self.ok(fmi2Terminate(self.c), "fmi2Terminate");
            self.ok(fmi2Reset(self.c), "fmi2Reset");
            let weights = CString::new(config.weights).unwrap();
            let vrs = BeamVrs::get();
            self.ok(
                fmi2SetInteger(
                    self.c,
                    [vrs.fidelity, vrs.friction_law].as_ptr(),
                    2,
                    [config.fidelity.code(), config.law.code()].as_ptr(),
                ),
                "fmi2SetInteger",
            );
            self.ok(
                fmi2SetString(self.c, &vrs.weights, 1, &weights.as_ptr()),
                "fmi2SetString",
            );
        }
        self.initialize();
        self.k = 0;
        std::mem::take(&mut self.points)
    }

    fn finish(mut self) -> Vec<Point> {
        unsafe {
            self.ok(fmi2Terminate(self.c), "fmi2Terminate");
            fmi2FreeInstance(self.c);
        }
        self.c = null_mut();
        std::mem::take(&mut self.points)
    }
}

impl Drop for Run {
    fn drop(&mut self) {
        if !self.c.is_null() {
            unsafe { fmi2FreeInstance(self.c) };
        }
    }
}

fn repository_uri() -> String {
    file_uri(&weights_dir())
}

fn alone(config: Config) -> Vec<Point> {
    let mut run = Run::start(config, &repository_uri());
    run.run_to_end();
    run.finish()
}

/// The first communication point where two runs differ.
fn first_difference(a: &[Point], b: &[Point]) -> Option<usize> {
    if a.len() != b.len() {
        return Some(a.len().min(b.len()));
    }
    a.iter().zip(b).position(|(x, y)| x != y)
}

const THREADS: usize = 8;
const PER_THREAD: usize = 4;

/// Instance `j` of thread `t`: the laws rotate, and two instances are at beam fidelity.
fn config_of(t: usize, j: usize) -> Config {
    let (law, weights) = LAWS[(t + j) % LAWS.len()];
    let fidelity = if (t, j) == (0, 0) || (t, j) == (5, 2) {
        FidelityLevel::Beam
    } else {
        FidelityLevel::Modal
    };
    Config {
        fidelity,
        law,
        weights,
    }
}

#[test]
fn thirty_two_instances_in_eight_threads_equal_one_instance_alone_bit_for_bit() {
    let start = std::time::Instant::now();
    let mut configs: Vec<Config> = (0..THREADS)
        .flat_map(|t| (0..PER_THREAD).map(move |j| config_of(t, j)))
        .collect();
    configs.sort_by_key(|c| (c.fidelity.code(), c.law.code(), c.weights));
    configs.dedup();
    let references: Vec<(Config, Vec<Point>)> = configs.iter().map(|&c| (c, alone(c))).collect();
    let reference = |config: Config| {
        &references
            .iter()
            .find(|(c, _)| *c == config)
            .expect("a reference for every configuration")
            .1
    };
    // Every configuration gives different outputs, so an instance that picked up
    // another's data would show.
    for (k, (a, ra)) in references.iter().enumerate() {
        for (b, rb) in &references[k + 1..] {
            assert!(first_difference(ra, rb).is_some(), "{a:?} and {b:?} agree");
        }
    }
    let alone_time = start.elapsed();

    let barrier = Barrier::new(THREADS);
    let uri = repository_uri();
    let results: Vec<Vec<Vec<Point>>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..THREADS)
            .map(|t| {
                let (barrier, uri) = (&barrier, &uri);
                scope.spawn(move || {
                    let mut runs: Vec<Run> = (0..PER_THREAD)
                        .map(|j| Run::start(config_of(t, j), uri))
                        .collect();
                    barrier.wait();
                    // Interleaved: one communication step of each instance in turn.
                    for _ in 0..STEPS {
                        for run in &mut runs {
                            run.step();
                        }
                    }
                    runs.into_iter().map(Run::finish).collect::<Vec<_>>()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });

    let mut checked = 0;
    for (t, runs) in results.iter().enumerate() {
        for (j, points) in runs.iter().enumerate() {
            let config = config_of(t, j);
            assert_eq!(
                first_difference(points, reference(config)),
                None,
                "thread {t}, instance {j} ({config:?}) differs from the instance alone"
            );
            checked += 1;
        }
    }
    let transitions: Vec<u64> = references.iter().map(|(_, r)| r[STEPS - 1][6]).collect();
    println!(
        "{checked} instances in {THREADS} threads, {STEPS} points each: bit-identical to {} \
         instances alone (stick/slip transitions at 1.2 s: {transitions:?}); alone {:.2} s, \
         total {:.2} s",
        references.len(),
        alone_time.as_secs_f64(),
        start.elapsed().as_secs_f64()
    );
}

#[test]
fn a_run_after_fmi2_reset_repeats_the_first_bit_for_bit() {
    for config in [
        config_of(0, 1),
        Config {
            fidelity: FidelityLevel::Beam,
            law: FrictionLawKind::Neural,
            weights: "paper-signed.json",
        },
    ] {
        let mut run = Run::start(config, &repository_uri());
        run.run_to_end();
        let first = run.reset(config);
        run.run_to_end();
        let second = run.finish();
        assert_eq!(first_difference(&first, &second), None, "{config:?}");
        assert!(first[STEPS - 1][6] > 0, "no stick/slip transition");
    }
}

// ---------------------------------------------------------------------------------------
// Resource locations.

fn errors(log: &[Entry]) -> Vec<&str> {
    log.iter()
        .filter(|e| e.status == ERROR && e.category == "logStatusError" && e.format == "%s")
        .map(|e| e.message.as_str())
        .collect()
}

/// Instantiation is refused (NULL) with an fmi2Error message from fmi2Instantiate that
/// contains every one of `needles`.
fn assert_refused(kind: FmuKind, uri: Option<&str>, needles: &[&str]) {
    let (c, log) = instantiate_at(kind, uri);
    if !c.is_null() {
        unsafe { fmi2FreeInstance(c) };
        panic!("{kind:?} instantiated with resource location {uri:?}");
    }
    let errors = errors(&log);
    assert!(
        errors.iter().any(|m| m.starts_with("fmi2Instantiate: ")
            && needles.iter().all(|n| m.contains(n))
            && names_paths_once(m, needles)),
        "{kind:?}, {uri:?}: no error message containing {needles:?} (each path once); logged {log:?}"
    );
}

/// Whether every needle that is a path occurs in `message` exactly once (the reader
/// names the file; no layer above adds it again).
fn names_paths_once(message: &str, needles: &[&str]) -> bool {
    needles
        .iter()
        .filter(|n| n.contains('/'))
        .all(|n| message.matches(n).count() == 1)
}

/// The first 0.6 s (past breakaway at 0.4 s) of the neural-law beam (modal) with resources at `uri` and weights
/// `weights` (a name in resources/ or an absolute path).
fn neural_run(uri: &str, weights: &'static str) -> Vec<Point> {
    let config = Config {
        fidelity: FidelityLevel::Modal,
        law: FrictionLawKind::Neural,
        weights,
    };
    let mut run = Run::start(config, uri);
    for _ in 0..600 {
        run.step();
    }
    run.finish()
}

#[test]
fn resource_uris_with_spaces_and_non_ascii_characters_work_encoded_and_raw() {
    let root = odd_temp_dir("uri");
    let dir = copy_resources(&root);
    let raw = dir.display().to_string();
    let encoded = file_uri(&dir);
    assert!(encoded.contains("%20") && encoded.contains("%C3%BC"));
    let uris = [
        encoded.clone(),
        format!("{encoded}/"),
        format!("file://{raw}"),
        format!("file://{raw}/"),
        encoded.replacen("file://", "file://localhost", 1),
        encoded.replacen("file://", "file:", 1),
    ];
    for uri in &uris {
        for kind in FmuKind::ALL {
            let (c, log) = instantiate_at(kind, Some(uri));
            assert!(!c.is_null(), "{kind:?} at {uri}: {log:?}");
            assert!(errors(&log).is_empty());
            unsafe { fmi2FreeInstance(c) };
        }
    }

    // The weights are read from that folder: swap the two networks there, and the beam's
    // run with "paper-plain.json" is the repository's run with "paper-signed.json".
    let plain = dir.join("paper-plain.json");
    let signed = dir.join("paper-signed.json");
    std::fs::rename(&plain, dir.join("swap")).unwrap();
    std::fs::rename(&signed, &plain).unwrap();
    std::fs::rename(dir.join("swap"), &signed).unwrap();
    let repository = repository_uri();
    let expected = neural_run(&repository, "paper-signed.json");
    assert!(first_difference(&expected, &neural_run(&repository, "paper-plain.json")).is_some());
    for uri in [&uris[0], &uris[2]] {
        assert_eq!(
            first_difference(&neural_run(uri, "paper-plain.json"), &expected),
            None,
            "{uri}"
        );
    }
    // An absolute weights path with the same characters (the repository's plain network,
    // now named paper-signed.json in the copy).
    let absolute: &'static str = signed.display().to_string().leak();
    assert_eq!(
        first_difference(
            &neural_run(&repository, absolute),
            &neural_run(&repository, "paper-plain.json")
        ),
        None
    );
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn a_missing_resources_folder_fails_instantiation_with_a_reason() {
    let root = odd_temp_dir("missing");
    let missing = root.join("resources");
    for uri in [file_uri(&missing), format!("file://{}", missing.display())] {
        for kind in FmuKind::ALL {
            // The message names the file it looked for, decoded.
            let file = missing.join("paper-plain.json").display().to_string();
            assert_refused(kind, Some(&uri), &[file.as_str(), "no such file"]);
        }
    }
}

/// A weights file that cannot be used is reported where the network is first needed:
/// NeuralFriction (whose default law is the network) refuses instantiation;
/// StickSlipBeam (default law exponential, the network read only for
/// friction.law = neural) instantiates, runs the exponential law, and refuses
/// fmi2ExitInitializationMode with the neural law. Each refusal logs all `needles`.
fn assert_weights_refused(uri: &str, needles: &[&str]) {
    assert_refused(FmuKind::NeuralFriction, Some(uri), needles);
    let vrs = BeamVrs::get();
    for (law, accepted) in [
        (FrictionLawKind::Exponential, true),
        (FrictionLawKind::Neural, false),
    ] {
        let (c, _) = instantiate_at(FmuKind::StickSlipBeam, Some(uri));
        assert!(
            !c.is_null(),
            "StickSlipBeam read the network at instantiation"
        );
        let log = Log::default();
        let functions = callbacks(&log);
        unsafe {
            fmi2FreeInstance(c);
            let guid = CString::new(FmuKind::StickSlipBeam.guid()).unwrap();
            let uri = CString::new(uri).unwrap();
            let c = fmi2Instantiate(
                c"resources".as_ptr(),
                1,
                guid.as_ptr(),
                uri.as_ptr(),
                &functions,
                0,
                0,
            );
            assert!(!c.is_null());
            assert_eq!(
                fmi2SetInteger(
                    c,
                    [vrs.fidelity].as_ptr(),
                    1,
                    [FidelityLevel::Modal.code()].as_ptr()
                ),
                OK
            );
            assert_eq!(
                fmi2SetInteger(c, [vrs.friction_law].as_ptr(), 1, [law.code()].as_ptr()),
                OK
            );
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            let status = fmi2ExitInitializationMode(c);
            if accepted {
                assert_eq!(status, OK, "{:?}", log.lock().unwrap());
                assert_eq!(fmi2DoStep(c, 0.0, 0.01, 1), OK);
            } else {
                assert_eq!(status, ERROR);
            }
            fmi2FreeInstance(c);
        }
        let entries = log.into_inner().unwrap();
        if !accepted {
            assert!(
                errors(&entries).iter().any(|m| {
                    m.starts_with("fmi2ExitInitializationMode")
                        && needles.iter().all(|n| m.contains(n))
                        && names_paths_once(m, needles)
                }),
                "no error containing {needles:?} (each path once): {entries:?}"
            );
        }
    }
}

#[test]
fn unreadable_or_corrupted_weights_give_a_reason_where_the_network_is_first_needed() {
    use std::os::unix::fs::PermissionsExt;
    let root = odd_temp_dir("weights");
    let dir = copy_resources(&root);
    let uri = file_uri(&dir);
    let plain = dir.join("paper-plain.json");
    let name = plain.display().to_string();

    std::fs::set_permissions(&plain, std::fs::Permissions::from_mode(0o000)).unwrap();
    if std::fs::read(&plain).is_ok() {
        println!(
            "note: skipped the unreadable-weights case: {} is still readable after chmod 000 \
             (running as root)",
            name
        );
    } else {
        assert_weights_refused(&uri, &[name.as_str(), "cannot be read"]);
    }
    std::fs::set_permissions(&plain, std::fs::Permissions::from_mode(0o644)).unwrap();

    // A read error at any privilege: a link to /proc/self/mem, a regular file whose read
    // at offset 0 fails (address 0 is never mapped).
    std::fs::remove_file(&plain).unwrap();
    std::os::unix::fs::symlink("/proc/self/mem", &plain).unwrap();
    if std::fs::read(&plain).is_ok() {
        println!("note: skipped the read-error case: /proc/self/mem reads here");
    } else {
        assert_weights_refused(&uri, &[name.as_str(), "cannot be read"]);
    }
    std::fs::remove_file(&plain).unwrap();

    let cases: [(&[u8], &str); 4] = [
        (b"{\"format\": 3", "not a valid model description"),
        (&[0xff, 0xfe, 0x00, 0x7b], "not UTF-8 text (byte 0"),
        (b"", "the file is empty"),
        (b"{\"weights\": [1, 2, 3]}", "format is '(missing)'"),
    ];
    for (contents, reason) in cases {
        std::fs::write(&plain, contents).unwrap();
        assert_weights_refused(&uri, &["weights file", name.as_str(), reason]);
    }

    // Special files are refused by their type, before anything is read: /dev/zero would
    // be read forever, a FIFO would block the importer.
    std::fs::remove_file(&plain).unwrap();
    // (The default weights' type is checked at instantiation, so both FMUs refuse there.)
    std::os::unix::fs::symlink("/dev/zero", &plain).unwrap();
    for kind in FmuKind::ALL {
        assert_refused(
            kind,
            Some(&uri),
            &[name.as_str(), "is a character device, not a regular file"],
        );
    }
    std::fs::remove_file(&plain).unwrap();
    let fifo = std::process::Command::new("mkfifo").arg(&plain).status();
    if fifo.is_ok_and(|s| s.success()) {
        for kind in FmuKind::ALL {
            assert_refused(
                kind,
                Some(&uri),
                &[name.as_str(), "is a FIFO (named pipe), not a regular file"],
            );
        }
        std::fs::remove_file(&plain).unwrap();
    } else {
        println!("note: skipped the FIFO case: mkfifo is not available");
    }

    // An ONNX file (found by its first byte, whatever its name) whose metadata does not
    // describe the features: the reason names the metadata key and the import flags.
    let shipped = stickslip::neural::NeuralLaw::paper_default().unwrap();
    let mut bare = stickslip_tests::onnx::export(
        shipped.model(),
        stickslip_tests::onnx::Exporter::Torch,
        true,
    );
    bare.metadata.clear();
    std::fs::write(&plain, bare.encode()).unwrap();
    assert_weights_refused(
        &uri,
        &[
            name.as_str(),
            "stickslip.features",
            "--feature NAME:ROLE:UNIT:MIN:MAX",
        ],
    );

    // A folder where the file should be.
    std::fs::remove_file(&plain).unwrap();
    std::fs::create_dir(&plain).unwrap();
    for kind in FmuKind::ALL {
        assert_refused(
            kind,
            Some(&uri),
            &[name.as_str(), "is a directory, not a file"],
        );
    }
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn non_file_uris_and_null_fail_instantiation_with_a_reason() {
    let weights = weights_dir().display().to_string();
    let uris = [
        "http://example.com/StickSlipBeam/resources".to_string(),
        "https://example.com/resources/".to_string(),
        "ftp://example.com/resources".to_string(),
        // A file URI on another host, a bad escape, a relative path, nothing.
        format!("file://fileserver{weights}"),
        format!("file://{weights}%zz"),
        format!("file://{weights}%C3"),
        weights.clone(),
        "weights".to_string(),
        String::new(),
    ];
    for kind in FmuKind::ALL {
        for uri in &uris {
            assert_refused(kind, Some(uri), &["fmuResourceLocation", "not a file URI"]);
        }
        assert_refused(kind, None, &["fmuResourceLocation", "NULL"]);
    }
}

// ---------------------------------------------------------------------------------------
// Memory: FMU states left at fmi2FreeInstance (counted by `allocations`).

/// An initialised NeuralFriction instance with `left` FMU states (from fmi2GetFMUstate
/// and fmi2DeSerializeFMUstate) that the importer does not free, freed at once.
unsafe fn instance_leaving_states(left: usize) {
    let log = Log::default();
    let functions = callbacks(&log);
    let guid = CString::new(FmuKind::NeuralFriction.guid()).unwrap();
    let uri = CString::new(repository_uri()).unwrap();
    let c = fmi2Instantiate(
        c"states".as_ptr(),
        1,
        guid.as_ptr(),
        uri.as_ptr(),
        &functions,
        0,
        0,
    );
    assert!(!c.is_null());
    assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi2EnterInitializationMode(c), OK);
    assert_eq!(fmi2ExitInitializationMode(c), OK);
    let mut bytes = Vec::new();
    for k in 0..left {
        let mut state = null_mut();
        if k % 2 == 0 {
            assert_eq!(fmi2GetFMUstate(c, &mut state), OK);
            let mut size = 0;
            assert_eq!(fmi2SerializedFMUstateSize(c, state, &mut size), OK);
            bytes = vec![0 as c_char; size];
            assert_eq!(
                fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size),
                OK
            );
        } else {
            assert_eq!(
                fmi2DeSerializeFMUstate(c, bytes.as_ptr(), bytes.len(), &mut state),
                OK
            );
        }
    }
    fmi2FreeInstance(c);
}

#[test]
fn fmi2_free_instance_frees_the_fmu_states_the_importer_did_not_free() {
    unsafe {
        // The first life sets up whatever this thread allocates once.
        instance_leaving_states(0);
        let before = live_bytes();
        instance_leaving_states(0);
        assert_eq!(live_bytes(), before, "an instance without states leaks");
        instance_leaving_states(4);
        assert_eq!(
            live_bytes() - before,
            0,
            "bytes left after fmi2FreeInstance of an instance with 4 unfreed FMU states"
        );
    }
}

#[test]
fn fmu_states_are_freed_by_their_own_instance_only() {
    let logs = [Log::default(), Log::default()];
    let functions = [callbacks(&logs[0]), callbacks(&logs[1])];
    let guid = CString::new(FmuKind::NeuralFriction.guid()).unwrap();
    let uri = CString::new(repository_uri()).unwrap();
    unsafe {
        let [a, b] = [0, 1].map(|k| {
            fmi2Instantiate(
                c"owner".as_ptr(),
                1,
                guid.as_ptr(),
                uri.as_ptr(),
                &functions[k],
                0,
                0,
            )
        });
        let mut state = null_mut();
        assert_eq!(fmi2GetFMUstate(a, &mut state), OK);
        let kept = state;
        assert_eq!(fmi2FreeFMUstate(b, &mut state), ERROR);
        assert_eq!(state, kept, "the pointer is left alone");
        let refused = logs[1].lock().unwrap();
        assert!(
            refused
                .iter()
                .any(|e| e.message.contains("not allocated by this instance")),
            "{refused:?}"
        );
        drop(refused);
        assert_eq!(fmi2FreeFMUstate(a, &mut state), OK);
        assert!(state.is_null());
        // Freed already: a second free is refused, not a double free.
        state = kept;
        assert_eq!(fmi2FreeFMUstate(a, &mut state), ERROR);
        fmi2FreeInstance(a);
        fmi2FreeInstance(b);
    }
}

// ---------------------------------------------------------------------------------------
// The valgrind driver.

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static RELEASES: AtomicUsize = AtomicUsize::new(0);

unsafe extern "C" fn counting_calloc(n: libc::size_t, size: libc::size_t) -> *mut c_void {
    ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    libc::calloc(n, size)
}

unsafe extern "C" fn counting_free(p: *mut c_void) {
    RELEASES.fetch_add(1, Ordering::Relaxed);
    libc::free(p)
}

#[derive(Clone, Copy, Debug)]
enum Callbacks {
    Logger,
    NullLogger,
    LoggerAndMemory,
}

/// One instance through its whole life: parameters, initialisation, steps, reads, FMU
/// state through pointers and bytes, an error and the recovery from it, reset, and free.
/// One FMU state is deliberately left for fmi2FreeInstance to free (FMI 2.0.x section
/// 2.1.6: fmi2FreeInstance "frees all the allocated memory ... allocated by the functions
/// of the FMU interface").
unsafe fn life(kind: FmuKind, callbacks_kind: Callbacks, steps: usize) {
    let log = Box::new(Log::default());
    let mut functions = callbacks(&log);
    match callbacks_kind {
        Callbacks::Logger => {}
        Callbacks::NullLogger => functions.logger = None,
        Callbacks::LoggerAndMemory => {
            functions.allocateMemory = Some(counting_calloc);
            functions.freeMemory = Some(counting_free);
        }
    }
    let logging_on = matches!(callbacks_kind, Callbacks::Logger) as fmi2Boolean;
    let guid = CString::new(kind.guid()).unwrap();
    let uri = CString::new(repository_uri()).unwrap();
    let c = fmi2Instantiate(
        c"life".as_ptr(),
        1,
        guid.as_ptr(),
        uri.as_ptr(),
        &functions,
        0,
        logging_on,
    );
    assert!(!c.is_null());
    let ok = |status: fmi2Status, what: &str| assert_eq!(status, OK, "{what}");
    let vrs = BeamVrs::get();
    let (output, input, string_vr) = match kind {
        FmuKind::StickSlipBeam => {
            ok(
                fmi2SetInteger(
                    c,
                    [vrs.fidelity, vrs.friction_law].as_ptr(),
                    2,
                    [FidelityLevel::Modal.code(), FrictionLawKind::Neural.code()].as_ptr(),
                ),
                "fmi2SetInteger",
            );
            (
                vrs.real_outputs[0],
                vr::<StickSlipBeam>("belt_speed"),
                vrs.weights,
            )
        }
        FmuKind::NeuralFriction => (
            vr::<NeuralFriction>("friction_force"),
            vr::<NeuralFriction>("sliding_velocity"),
            vr::<NeuralFriction>("weights"),
        ),
    };
    let all = [
        c"logStatusError".as_ptr(),
        c"logEvents".as_ptr(),
        c"logCalls".as_ptr(),
    ];
    ok(
        fmi2SetDebugLogging(c, logging_on, 3, all.as_ptr()),
        "fmi2SetDebugLogging",
    );
    let weights = c"paper-plain.json";
    ok(
        fmi2SetString(c, &string_vr, 1, &weights.as_ptr()),
        "fmi2SetString",
    );
    let initialize = || {
        ok(
            fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 10.0),
            "fmi2SetupExperiment",
        );
        ok(
            fmi2EnterInitializationMode(c),
            "fmi2EnterInitializationMode",
        );
        let mut y = 0.0;
        ok(
            fmi2GetReal(c, &output, 1, &mut y),
            "fmi2GetReal in initialization mode",
        );
        ok(fmi2ExitInitializationMode(c), "fmi2ExitInitializationMode");
    };
    initialize();
    let mut t = 0.0;
    let step = |t: &mut f64, n: usize| {
        for k in 0..n {
            let v = 0.02 * (1.0 + (k % 7) as f64 * 0.01);
            ok(fmi2SetReal(c, &input, 1, &v), "fmi2SetReal");
            ok(fmi2DoStep(c, *t, 1e-3, 1), "fmi2DoStep");
            *t += 1e-3;
            let mut y = 0.0;
            ok(fmi2GetReal(c, &output, 1, &mut y), "fmi2GetReal");
            assert!(y.is_finite());
            let mut s = null();
            ok(fmi2GetString(c, &string_vr, 1, &mut s), "fmi2GetString");
            assert!(!s.is_null());
        }
    };
    step(&mut t, steps);

    let mut state = null_mut();
    ok(fmi2GetFMUstate(c, &mut state), "fmi2GetFMUstate");
    ok(
        fmi2GetFMUstate(c, &mut state),
        "fmi2GetFMUstate (overwrite)",
    );
    let t_saved = t;
    let mut size = 0;
    ok(fmi2SerializedFMUstateSize(c, state, &mut size), "size");
    let mut bytes = vec![0 as c_char; size];
    ok(
        fmi2SerializeFMUstate(c, state, bytes.as_mut_ptr(), size),
        "serialize",
    );
    let mut copy = null_mut();
    ok(
        fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size, &mut copy),
        "deserialize",
    );
    step(&mut t, steps / 4);

    // Errors, and the way back.
    assert_eq!(fmi2DoStep(c, t + 1.0, 1e-3, 1), ERROR);
    let mut bad = null_mut();
    assert_eq!(
        fmi2DeSerializeFMUstate(c, bytes.as_ptr(), size / 2, &mut bad),
        ERROR
    );
    assert!(bad.is_null());
    // Unknown and known swapped: an input is no unknown (NeuralFriction), and
    // StickSlipBeam has no directional derivatives at all.
    let mut d = 0.0;
    assert_eq!(
        fmi2GetDirectionalDerivative(c, &input, 1, &output, 1, &1.0, &mut d),
        ERROR
    );
    ok(fmi2SetFMUstate(c, copy), "fmi2SetFMUstate (deserialized)");
    t = t_saved;
    step(&mut t, steps / 4);
    ok(fmi2SetFMUstate(c, state), "fmi2SetFMUstate");
    t = t_saved;
    step(&mut t, steps / 4);
    ok(fmi2FreeFMUstate(c, &mut state), "fmi2FreeFMUstate");

    ok(fmi2Terminate(c), "fmi2Terminate");
    ok(fmi2Reset(c), "fmi2Reset");
    if kind == FmuKind::StickSlipBeam {
        ok(
            fmi2SetInteger(
                c,
                [vrs.fidelity, vrs.friction_law].as_ptr(),
                2,
                [
                    FidelityLevel::Modal.code(),
                    FrictionLawKind::Exponential.code(),
                ]
                .as_ptr(),
            ),
            "fmi2SetInteger",
        );
    }
    initialize();
    t = 0.0;
    step(&mut t, steps / 4);
    ok(fmi2Terminate(c), "fmi2Terminate");
    // `copy` is still allocated: fmi2FreeInstance frees it.
    fmi2FreeInstance(c);

    // Refused instantiations.
    let bad_guid = fmi2Instantiate(
        c"life".as_ptr(),
        1,
        c"{not-this-fmu}".as_ptr(),
        uri.as_ptr(),
        &functions,
        0,
        logging_on,
    );
    assert!(bad_guid.is_null());
    let nowhere = fmi2Instantiate(
        c"life".as_ptr(),
        1,
        guid.as_ptr(),
        c"file:///nonexistent/resources".as_ptr(),
        &functions,
        0,
        logging_on,
    );
    assert!(nowhere.is_null());
    if matches!(callbacks_kind, Callbacks::Logger) {
        assert!(!log.lock().unwrap().is_empty());
    }
}

/// Run by scripts/valgrind.sh under valgrind. STICKSLIP_VALGRIND_ROUNDS (default 2)
/// lives of each FMU with each kind of callbacks.
#[test]
#[ignore = "run by scripts/valgrind.sh"]
fn valgrind_driver_loop() {
    let rounds: usize = std::env::var("STICKSLIP_VALGRIND_ROUNDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2);
    for callbacks_kind in [
        Callbacks::Logger,
        Callbacks::NullLogger,
        Callbacks::LoggerAndMemory,
    ] {
        for _ in 0..rounds {
            for kind in FmuKind::ALL {
                unsafe { life(kind, callbacks_kind, 40) };
            }
        }
    }
    // The FMU declares canNotUseMemoryManagementFunctions = true and never calls them.
    assert_eq!(ALLOCATIONS.load(Ordering::Relaxed), 0);
    assert_eq!(RELEASES.load(Ordering::Relaxed), 0);
    println!("{rounds} rounds x 3 kinds of callbacks x 2 FMUs done");
}
