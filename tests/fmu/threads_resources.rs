//! Through the C ABI:
//! - many instances in many threads, interleaved, give the outputs of one instance alone,
//!   bit for bit; so does a run after fmi2Reset;
//! - resource locations: odd characters in the path (percent-encoded and raw), a missing
//!   folder, unreadable or corrupted weights, non-file URIs and NULL;
//! - `valgrind_driver_loop` (ignored): the loop that `scripts/valgrind.sh` runs under
//!   valgrind.
//!
//! The importer side and the paper-scene run the tests share are here; the tests are in
//! `threads`, `resource_locations`, `freed_states` and `valgrind_driver`.

use std::ffi::{c_char, c_void, CString};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Barrier;
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::scene::FidelityLevel;
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

/// The first communication point where two runs differ.
fn first_difference(a: &[Point], b: &[Point]) -> Option<usize> {
    if a.len() != b.len() {
        return Some(a.len().min(b.len()));
    }
    a.iter().zip(b).position(|(x, y)| x != y)
}

mod freed_states;
mod resource_locations;
mod threads;
mod valgrind_driver;
