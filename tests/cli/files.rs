//! Files a user hands in and files a command writes (issue 33): every input file that
//! cannot be read gets its own message naming the path once, and a command that fails
//! leaves no new output and an older file of the same name byte for byte as it was.

use std::path::{Path, PathBuf};

use super::stickslip;

fn scratch(test: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("stickslip-cli-files-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The fuzz seed network (PyTorch form, float64, tanh 2-4-1, described by its metadata).
fn onnx_seed() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus/onnx/seed-torch-f64-tanh-2-4-1.onnx")
}

/// The names in `dir`, sorted: what a command left there.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// One way a command takes an input file: its arguments around the path, the words
/// that open the message, whether the file is read as text, and the output the command
/// would write.
struct Slot {
    name: &'static str,
    extension: &'static str,
    args: fn(&str, &str) -> Vec<String>,
    prefix: &'static str,
    text: bool,
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

const SLOTS: [Slot; 6] = [
    Slot {
        name: "import-network SOURCE",
        extension: "onnx",
        args: |input, out| strings(&["import-network", input, "--out", out]),
        prefix: "weights file",
        text: false,
    },
    Slot {
        name: "import-network --check-data",
        extension: "csv",
        args: |input, out| {
            let seed = onnx_seed().display().to_string();
            strings(&["import-network", &seed, "--out", out, "--check-data", input])
        },
        prefix: "data file",
        text: true,
    },
    Slot {
        name: "simulate --weights",
        extension: "json",
        args: |input, out| {
            strings(&[
                "simulate",
                "--friction",
                "neural",
                "--weights",
                input,
                "--t-end",
                "0.001",
                "--out",
                out,
            ])
        },
        prefix: "friction.weights: weights file",
        text: true,
    },
    Slot {
        name: "simulate --scene",
        extension: "toml",
        args: |input, out| {
            strings(&[
                "simulate", "--scene", input, "--t-end", "0.001", "--out", out,
            ])
        },
        prefix: "scene file",
        text: true,
    },
    Slot {
        name: "train --data",
        extension: "csv",
        args: |input, out| {
            strings(&[
                "train",
                "--data",
                input,
                "--features",
                "v,Fn",
                "--target",
                "F",
                "--out",
                out,
                "--quiet",
            ])
        },
        prefix: "data file",
        text: true,
    },
    Slot {
        name: "train-memory --data",
        extension: "csv",
        args: |input, out| strings(&["train-memory", "--data", input, "--out", out, "--quiet"]),
        prefix: "records file",
        text: true,
    },
];

/// Runs `slot` on `input` and checks the last line of stderr is exactly
/// `error: {prefix} {input}: {reason}`, the path in it once, and that no output (nor a
/// temporary file) was left.
fn assert_refused(slot: &Slot, dir: &Path, input: &Path, reason: &str) {
    let line = refusal(slot, dir, input);
    let expected = format!("error: {} {}: {reason}", slot.prefix, input.display());
    assert_eq!(line, expected, "{}", slot.name);
}

/// Runs `slot` on `input`, checks that it failed naming the path once and left nothing;
/// returns the last line of stderr.
fn refusal(slot: &Slot, dir: &Path, input: &Path) -> String {
    let out = dir.join("out.file");
    let input_text = input.display().to_string();
    let before = listing(dir);
    let (ok, _, stderr) = stickslip(
        &(slot.args)(&input_text, &out.display().to_string())
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    assert!(!ok, "{}: {input_text} accepted", slot.name);
    assert_eq!(
        stderr.matches(&input_text).count(),
        1,
        "{}: {stderr}",
        slot.name
    );
    assert!(!out.exists(), "{}: wrote {}", slot.name, out.display());
    assert_eq!(listing(dir), before, "{}: left files behind", slot.name);
    stderr.lines().last().unwrap_or_default().to_string()
}

/// The binary run as user and group nobody (65534) through util-linux's setpriv, for
/// a permission that root would not feel.
fn as_nobody(args: &[String]) -> std::io::Result<std::process::Output> {
    std::process::Command::new("setpriv")
        .args(["--reuid=65534", "--regid=65534", "--clear-groups"])
        .arg(env!("CARGO_BIN_EXE_stickslip"))
        .args(args)
        .output()
}

/// Whether [`as_nobody`] works here (setpriv installed, the binary reachable by nobody).
fn nobody_can_run() -> bool {
    as_nobody(&["--version".to_string()]).is_ok_and(|out| out.status.success())
}

/// Missing, a directory, a device, a FIFO, empty, not UTF-8 where text is read, and
/// unreadable: each refused with its own words, by every command that reads a file.
#[test]
fn every_bad_input_file_has_its_own_message_naming_the_path_once() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("inputs");
    let mut unreadable_checked = false;
    for slot in &SLOTS {
        let named = |what: &str| dir.join(format!("{what}.{}", slot.extension));
        assert_refused(slot, &dir, &named("missing"), "no such file");

        let folder = named("folder");
        std::fs::create_dir(&folder).unwrap();
        assert_refused(slot, &dir, &folder, "is a directory, not a file");
        std::fs::remove_dir(&folder).unwrap();

        // /dev/zero under the slot's name: refused by its type, never read.
        let zero = named("zero");
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        assert_refused(
            slot,
            &dir,
            &zero,
            "is a character device, not a regular file",
        );
        assert_refused(
            slot,
            &dir,
            Path::new("/dev/zero"),
            "is a character device, not a regular file",
        );
        std::fs::remove_file(&zero).unwrap();

        let fifo = named("fifo");
        if std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success())
        {
            assert_refused(
                slot,
                &dir,
                &fifo,
                "is a FIFO (named pipe), not a regular file",
            );
            std::fs::remove_file(&fifo).unwrap();
        } else {
            println!("note: skipped the FIFO case: mkfifo is not available");
        }

        let empty = named("empty");
        std::fs::write(&empty, b"").unwrap();
        assert_refused(slot, &dir, &empty, "the file is empty");
        std::fs::remove_file(&empty).unwrap();

        if slot.text {
            let latin1 = named("latin1");
            std::fs::write(&latin1, b"v,F_n,F\n\xb5,1,2\n").unwrap();
            assert_refused(
                slot,
                &dir,
                &latin1,
                "not UTF-8 text (byte 8 is not part of a UTF-8 character)",
            );
            std::fs::remove_file(&latin1).unwrap();
        }

        // A regular file whose read fails at any privilege: /proc/self/mem at offset 0
        // (address 0 is never mapped), with the system's words for the error.
        let mem = named("mem");
        std::os::unix::fs::symlink("/proc/self/mem", &mem).unwrap();
        let line = refusal(slot, &dir, &mem);
        let expected = format!("error: {} {}: cannot be read: ", slot.prefix, mem.display());
        assert!(line.starts_with(&expected), "{}: {line}", slot.name);
        std::fs::remove_file(&mem).unwrap();

        let locked = named("locked");
        std::fs::write(&locked, b"x").unwrap();
        std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o000)).unwrap();
        if std::fs::read(&locked).is_err() {
            assert_refused(slot, &dir, &locked, "cannot be read: permission denied");
            unreadable_checked = true;
        } else if nobody_can_run() {
            // Root reads it anyway: the command runs as nobody instead.
            let out = as_nobody(&(slot.args)(
                &locked.display().to_string(),
                &dir.join("out.file").display().to_string(),
            ))
            .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{}", slot.name);
            let expected = format!(
                "error: {} {}: cannot be read: permission denied",
                slot.prefix,
                locked.display()
            );
            assert_eq!(
                stderr.lines().last(),
                Some(expected.as_str()),
                "{}",
                slot.name
            );
            unreadable_checked = true;
        }
        std::fs::remove_file(&locked).unwrap();
    }
    if !unreadable_checked {
        println!(
            "note: skipped the unreadable-file case: chmod 000 does not deny (root) and \
             setpriv cannot run the binary as nobody"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The case the issue found: `--check-data` naming a column the file lacks fails after
/// the conversion, and no weights file is written; an older one stays byte for byte.
#[test]
fn a_failed_check_writes_no_weights_and_keeps_the_old_file() {
    let dir = scratch("check");
    let data = dir.join("data.csv");
    // The seed's features are sliding_velocity and normal_force; the target is missing.
    std::fs::write(&data, "sliding_velocity[m/s],normal_force[N]\n0.01,100\n").unwrap();
    let out = dir.join("weights.json");
    let args = |out: &Path| {
        vec![
            "import-network".to_string(),
            onnx_seed().display().to_string(),
            "--out".into(),
            out.display().to_string(),
            "--check-data".into(),
            data.display().to_string(),
        ]
    };
    let run = |args: Vec<String>| stickslip(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let (ok, stdout, stderr) = run(args(&out));
    assert!(!ok, "{stdout}");
    assert!(
        stderr.contains("no column named 'friction_force' in the header"),
        "{stderr}"
    );
    assert!(!stdout.contains("wrote"), "{stdout}");
    assert_eq!(listing(&dir), ["data.csv"]);

    let old = b"{\"an older file\": true}\n";
    std::fs::write(&out, old).unwrap();
    let (ok, _, _) = run(args(&out));
    assert!(!ok);
    assert_eq!(std::fs::read(&out).unwrap(), old);
    assert_eq!(listing(&dir), ["data.csv", "weights.json"]);

    // With the target column the same command succeeds and replaces the file.
    std::fs::write(
        &data,
        "sliding_velocity[m/s],normal_force[N],friction_force[N]\n0.01,100,40\n0.02,100,39\n",
    )
    .unwrap();
    let (ok, _, stderr) = run(args(&out));
    assert!(ok, "{stderr}");
    assert_ne!(std::fs::read(&out).unwrap(), old);
    assert_eq!(listing(&dir), ["data.csv", "weights.json"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `simulate --out --summary-json`: both or neither. A summary path that is a folder
/// fails the command after the run, and the CSV (new or old) is not touched.
#[test]
fn simulate_writes_both_outputs_or_neither() {
    let dir = scratch("simulate");
    let csv = dir.join("run.csv");
    let folder = dir.join("summary.json");
    std::fs::create_dir(&folder).unwrap();
    let args = [
        "simulate",
        "--fidelity",
        "modal",
        "--t-end",
        "0.01",
        "--out",
        csv.to_str().unwrap(),
        "--summary-json",
        folder.to_str().unwrap(),
    ];
    let (ok, _, stderr) = stickslip(&args);
    assert!(!ok);
    assert_eq!(
        stderr.lines().last(),
        Some(
            format!(
                "error: cannot write {}: it is a directory",
                folder.display()
            )
            .as_str()
        )
    );
    assert_eq!(listing(&dir), ["summary.json"]);
    let old = b"t,tip_deflection\n";
    std::fs::write(&csv, old).unwrap();
    let (ok, _, _) = stickslip(&args);
    assert!(!ok);
    assert_eq!(std::fs::read(&csv).unwrap(), old);
    assert_eq!(listing(&dir), ["run.csv", "summary.json"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `train`: the weights, report, history and exported data are written after training,
/// all or none. A report path that is a folder fails the command at the end: no
/// weights, no exported data, and an older weights file is kept.
#[test]
fn train_writes_all_outputs_or_none() {
    let dir = scratch("train");
    let weights = dir.join("w.json");
    let report = dir.join("report.json");
    std::fs::create_dir(&report).unwrap();
    let export = dir.join("split");
    let history = dir.join("history.csv");
    let old = b"{\"older weights\": 1}\n";
    std::fs::write(&weights, old).unwrap();
    let args = [
        "train",
        "--samples",
        "40",
        "--layers",
        "3",
        "--iterations",
        "2",
        "--quiet",
        "--out",
        weights.to_str().unwrap(),
        "--history",
        history.to_str().unwrap(),
        "--report",
        report.to_str().unwrap(),
        "--export-data",
        export.to_str().unwrap(),
    ];
    let (ok, stdout, stderr) = stickslip(&args);
    assert!(!ok, "{stdout}");
    assert_eq!(
        stderr.lines().last(),
        Some(
            format!(
                "error: cannot write {}: it is a directory",
                report.display()
            )
            .as_str()
        )
    );
    assert_eq!(std::fs::read(&weights).unwrap(), old);
    assert_eq!(listing(&dir), ["report.json", "w.json"]);

    std::fs::remove_dir(&report).unwrap();
    let (ok, _, stderr) = stickslip(&args);
    assert!(ok, "{stderr}");
    assert_ne!(std::fs::read(&weights).unwrap(), old);
    assert_eq!(
        listing(&dir),
        ["history.csv", "report.json", "split", "w.json"]
    );
    assert_eq!(listing(&export), ["test.csv", "train.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `train-memory`: the weights and the records are written after training, together.
#[test]
fn train_memory_writes_all_outputs_or_none() {
    let dir = scratch("train-memory");
    let weights = dir.join("m.json");
    let records = dir.join("records.csv");
    let folder = dir.join("steps.csv");
    std::fs::create_dir(&folder).unwrap();
    let args = [
        "train-memory",
        "--iterations",
        "1",
        "--hidden",
        "2",
        "--quiet",
        "--out",
        weights.to_str().unwrap(),
        "--export-data",
        records.to_str().unwrap(),
        "--step-response",
        folder.to_str().unwrap(),
    ];
    let (ok, stdout, stderr) = stickslip(&args);
    assert!(!ok, "{stdout}");
    assert_eq!(
        stderr.lines().last(),
        Some(
            format!(
                "error: cannot write {}: it is a directory",
                folder.display()
            )
            .as_str()
        )
    );
    assert_eq!(listing(&dir), ["steps.csv"]);
    std::fs::remove_dir_all(&dir).unwrap();
}
