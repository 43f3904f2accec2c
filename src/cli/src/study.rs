//! The `study` command of the `stickslip` binary: speed against accuracy over a grid of
//! configurations (`stickslip::study`), and with `--verify-auto` the check that
//! `fidelity = auto` meets its tolerance (`stickslip::auto`).

use crate::choice::parser;
use crate::error::CliError;
use clap::Args;
use std::path::PathBuf;
use stickslip::auto::{AutoError, Verification};
use stickslip::files::{write_atomically, Outputs};
use stickslip::neural::inference::Inference;
use stickslip::scene::{Scene, Scheme};
use stickslip::study::{
    csv_line, front_of, front_points, Grid, Law, Progress, Study, StudyError, CSV_HEADER,
};

/// Arguments of `stickslip study`.
#[derive(Args, Debug, Clone)]
pub struct StudyArgs {
    /// Scene file (.toml or .json); its fidelity, time step and integrator are replaced
    /// by each configuration of the grid. Default: the paper's scene.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// End time (s) of every run.
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Modal levels: numbers of modes (comma-separated; empty for none).
    #[arg(long, value_delimiter = ',', num_args = 0..)]
    pub modes: Option<Vec<usize>>,
    /// Beam levels: numbers of elements.
    #[arg(long, value_delimiter = ',', num_args = 0..)]
    pub elements: Option<Vec<usize>>,
    /// Plane-stress levels: element sizes (m).
    #[arg(long, value_delimiter = ',', num_args = 0..)]
    pub element_sizes: Option<Vec<f64>>,
    /// Modal reductions of the plane-stress mesh: SIZE:MODES pairs, element size (m)
    /// and number of modes, e.g. 0.02:5,0.005:20 (empty for none).
    #[arg(long, value_parser = size_and_modes, value_delimiter = ',', num_args = 0..)]
    pub plane_stress_modal: Option<Vec<(f64, usize)>>,
    /// Time steps (s); each must divide 1 ms.
    #[arg(long, value_delimiter = ',')]
    pub dts: Option<Vec<f64>>,
    /// Integrators.
    #[arg(long, value_parser = parser::<Scheme>(), value_delimiter = ',')]
    pub integrators: Option<Vec<Scheme>>,
    /// Evaluations of a neural law (speed for accuracy), each against the reference
    /// with the exact network; laws other than neural ignore it. Default: the scene's
    /// own only.
    #[arg(long, value_parser = parser::<Inference>(), value_delimiter = ',')]
    pub inferences: Option<Vec<Inference>>,
    /// The friction-law axis: laws (comma-separated), each a scene law other than
    /// external, or neural:PATH for a network's weights file (the learned law with
    /// memory: neural:weights/rate-and-state-learned.json). Each law is compared with
    /// its own reference and has its own front. Default: the scene's law only.
    #[arg(long, value_parser = law, value_delimiter = ',')]
    pub laws: Option<Vec<Law>>,
    /// Output folder: study.csv (every run), front.json (the scene law's Pareto front)
    /// and, with --laws, front-LAW.json per law.
    #[arg(long, default_value = "out/study")]
    pub out: PathBuf,
    /// Also write the front to this file (the `auto` fidelity reads
    /// data/pareto_front.json).
    #[arg(long)]
    pub write_front: Option<PathBuf>,
    /// After the study, check `fidelity = auto` (with the shipped front) at these
    /// tolerances (m) on each of `stickslip::auto::verification_scenes`, each against
    /// its own reference run.
    #[arg(long, value_delimiter = ',')]
    pub verify_auto: Option<Vec<f64>>,
    /// With `--verify-auto`: only the verification scenes whose names contain one of
    /// these words (comma-separated), so that a long verification can be split.
    #[arg(long, value_delimiter = ',', requires = "verify_auto")]
    pub auto_scenes: Option<Vec<String>>,
    /// With `--verify-auto`: verify on the scenes with laws with state
    /// (`stickslip::auto::verification_scenes_with_state`, the learned law's weights
    /// from weights/rate-and-state-learned.json) instead; each is chosen for with its
    /// law's own front. Their reference needs the laws' converged step: give the study
    /// a grid whose finest point is 40 modes of the 0.005 m mesh at 2.5e-6 s.
    #[arg(long, requires = "verify_auto")]
    pub auto_with_state: bool,
}

/// One SIZE:MODES pair of `--plane-stress-modal`.
fn size_and_modes(text: &str) -> Result<(f64, usize), String> {
    let usage = || {
        format!(
            "'{text}': expected SIZE:MODES, an element size (m) and a number of modes, e.g. 0.02:5"
        )
    };
    let (size, modes) = text.split_once(':').ok_or_else(usage)?;
    let size: f64 = size.trim().parse().map_err(|_| usage())?;
    let modes: usize = modes.trim().parse().map_err(|_| usage())?;
    Ok((size, modes))
}

/// One friction law of `--laws`.
fn law(text: &str) -> Result<Law, String> {
    text.parse()
        .map_err(|e: stickslip::study::LawError| e.to_string())
}

/// `stickslip study`: the grid, each law's reference, the CSV and the fronts.
pub fn study(args: &StudyArgs) -> Result<(), CliError> {
    let mut scene = match &args.scene {
        Some(path) => Scene::load(path)?.into_scene(),
        None => Scene::default(),
    };
    if let Some(t) = args.t_end {
        scene.time.end = t;
    }
    let grid = grid_of(args);
    let reference_configuration = grid.finest().ok_or(CliError::EmptyGrid)?;
    // front.json (and --write-front, what `auto` reads) is the scene law's front; a law
    // axis without the scene's law has none.
    let scene_law = Law::of_scene(&scene).map_err(study_error)?;
    let laws = grid.laws_or(scene_law.clone());
    if !laws.contains(&scene_law) && args.write_front.is_some() {
        return Err(CliError::WriteFrontWithoutSceneLaw {
            law: scene_law.to_string(),
        });
    }
    // The folder is made before the runs, so that hours of runs are not lost to a
    // folder that cannot be made; the files in it are written after them.
    std::fs::create_dir_all(&args.out).map_err(|source| CliError::Folder {
        path: args.out.clone(),
        source,
    })?;
    let runs: usize = laws.iter().map(|l| grid.configurations_for(l).len()).sum();
    eprintln!(
        "study: {runs} runs ({} laws), end time {} s; reference {reference_configuration} per law",
        laws.len(),
        scene.time.end
    );
    let study = stickslip::study::run(&scene, &grid, print_progress).map_err(study_error)?;
    let end = scene.time.end;
    let written = write_study(args, &study, &grid, &laws, &scene_law, end)?;
    for law in &laws {
        print_front(&study, law, end);
    }
    println!(
        "{} runs in {}, {} on the fronts, {} failed; fronts in {}",
        study.rows.len() + study.references.len(),
        written[0].display(),
        study.rows.iter().filter(|r| r.on_front).count(),
        study.failures.len(),
        written[1..]
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    for (law, f) in &study.failures {
        println!("failed: {law} {}: {}", f.configuration, f.reason);
    }
    if let Some(tolerances) = &args.verify_auto {
        verify_auto(
            &scene,
            tolerances,
            args.auto_scenes.as_deref(),
            args.auto_with_state,
            reference_configuration,
            &args.out,
        )
        .map_err(|source| CliError::AfterWritten {
            written: written.iter().map(|p| p.display().to_string()).collect(),
            source: Box::new(source),
        })?;
    }
    Ok(())
}

/// The grid of the arguments, [`Grid::full`]'s axis where an argument is not given.
fn grid_of(args: &StudyArgs) -> Grid {
    let full = Grid::full();
    Grid {
        modes: args.modes.clone().unwrap_or(full.modes),
        beam_elements: args.elements.clone().unwrap_or(full.beam_elements),
        element_sizes: args.element_sizes.clone().unwrap_or(full.element_sizes),
        plane_stress_modal: args
            .plane_stress_modal
            .clone()
            .unwrap_or(full.plane_stress_modal),
        time_steps: args.dts.clone().unwrap_or(full.time_steps),
        schemes: match &args.integrators {
            Some(list) => list.clone(),
            None => full.schemes,
        },
        inferences: args.inferences.clone().unwrap_or(full.inferences),
        laws: args.laws.clone().unwrap_or(full.laws),
    }
}

/// One line on stderr per reference, run and failure as the study makes them.
fn print_progress(progress: Progress<'_>) {
    match progress {
        Progress::Reference(r) => eprintln!(
            "reference of {}: {}: {:.3} s",
            r.law, r.measured.configuration, r.measured.seconds
        ),
        Progress::Row { index, total, row } => eprintln!(
            "[{index}/{total}] {} {}: {:.3} s, RMS error {:.3e} m",
            row.law, row.measured.configuration, row.measured.seconds, row.errors.rms
        ),
        Progress::Failed {
            index,
            total,
            law,
            failed,
        } => eprintln!(
            "[{index}/{total}] {law} {}: failed: {}",
            failed.configuration, failed.reason
        ),
    }
}

/// Writes study.csv (every run, `end` (s) the runs' end time) and the fronts: the scene
/// law's to front.json and `--write-front`, and with a law axis each law's to
/// front-LAW.json; the table and the fronts together, or none of them. Returns the
/// paths written, the table first.
fn write_study(
    args: &StudyArgs,
    study: &Study,
    grid: &Grid,
    laws: &[Law],
    scene_law: &Law,
    end: f64,
) -> Result<Vec<PathBuf>, CliError> {
    let csv_path = args.out.join("study.csv");
    let mut csv = String::from(CSV_HEADER);
    csv.push('\n');
    for row in &study.rows {
        csv += &csv_line(row, end);
        csv.push('\n');
    }
    let mut outputs = Outputs::new();
    outputs.add(&csv_path, csv)?;
    let mut written = vec![csv_path];
    for law in laws {
        let mut paths = Vec::new();
        if law == scene_law {
            paths.push(args.out.join("front.json"));
            paths.extend(args.write_front.clone());
        }
        if !grid.laws.is_empty() {
            paths.push(args.out.join(format!("front-{}.json", law.slug())));
        }
        let points = front_points(&front_of(&study.rows, law));
        for path in paths {
            let json = serde_json::to_string_pretty(&points).map_err(|source| CliError::Json {
                path: path.clone(),
                source,
            })?;
            outputs.add(&path, &json)?;
            written.push(path);
        }
    }
    outputs.commit()?;
    Ok(written)
}

fn study_error(e: impl Into<StudyError>) -> CliError {
    CliError::Study(Box::new(e.into()))
}

/// `law`'s reference and Pareto front as a Markdown table.
fn print_front(study: &Study, law: &Law, end_time: f64) {
    if let Some(r) = study.reference(law) {
        println!(
            "{law}: reference {}: {} dofs, {:.2} s",
            r.measured.configuration, r.measured.dofs, r.measured.seconds
        );
    }
    println!();
    println!("Pareto front of {law} (RMS tip-deflection error against wall time), cheapest first:");
    println!();
    println!("| configuration | dofs | wall (s) | x real time | breakaway (ms) | 1st slip (ms) | period (ms) | corridor (um) | RMS (um) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let ms = |v: Option<f64>| v.map_or("-".into(), |v| format!("{:.3}", v * 1e3));
    for row in front_of(&study.rows, law) {
        let e = &row.errors;
        println!(
            "| {} | {} | {:.4} | {:.0} | {} | {} | {} | {} | {:.3} |",
            row.measured.configuration,
            row.measured.dofs,
            row.measured.seconds,
            end_time / row.measured.seconds,
            ms(e.breakaway),
            ms(e.first_slip_duration),
            ms(e.period),
            e.corridor.map_or("-".into(), |v| format!("{:.3}", v * 1e6)),
            e.rms * 1e6
        );
    }
    println!();
}

/// A configuration label as one CSV field (its commas become spaces).
fn csv_field(label: &str) -> String {
    label.replace(", ", " ")
}

/// `study --verify-auto`: on each verification scene and tolerance, the `auto` choice
/// must meet the tolerance against the scene's reference, and the next cheaper point
/// of the front must not.
fn verify_auto(
    base: &Scene,
    tolerances: &[f64],
    only: Option<&[String]>,
    with_state: bool,
    reference_configuration: stickslip::study::Configuration,
    out: &std::path::Path,
) -> Result<(), CliError> {
    use stickslip::auto::{
        finer, front_for, verification_scenes, verification_scenes_with_state, verify,
        window_deviation, ShippedFront,
    };
    let all = if with_state {
        verification_scenes_with_state("weights/rate-and-state-learned.json")
    } else {
        verification_scenes()
    };
    let scenes: Vec<_> = all
        .into_iter()
        .filter(|(name, _)| {
            only.is_none_or(|words| words.iter().any(|w| name.contains(w.as_str())))
        })
        .collect();
    let finer_configuration = finer(reference_configuration);
    println!();
    println!(
        "fidelity = auto on {} scenes (each with its law's shipped front); true error against each scene's {reference_configuration} over the whole run, 0 to {} s; each reference checked against {finer_configuration}:",
        scenes.len(),
        base.time.end
    );
    println!();
    println!("The estimate bounds the largest tip deviation over the whole run (stickslip::auto::choose, its reach in the 'over' column); true errors are the largest and the RMS tip deviation from the reference over the whole run.");
    println!();
    println!("| scene | reference vs finer (um) | tolerance (um) | choice | over | estimated (um) | true largest (um) | true RMS (um) | wall (s) | drift (ms/s) | next cheaper | its true largest (um) | calibration (s) | runs to t (s) | holds |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut csv = String::from(
        "scene,end_s,reference_vs_finer_m,tolerance_m,choice,over,estimated_m,true_largest_m,true_rms_m,wall_s,drift_rate,cheaper,cheaper_true_largest_m,calibration_s,calibration_runs,calibration_window_s,holds\n",
    );
    let mut failures = 0;
    let cases = tolerances.len() * scenes.len();
    for (name, mut scene) in scenes {
        scene.time.end = base.time.end;
        let law = crate::scene_args::law_of(&scene.clone().check()?)?;
        let front = front_for(&scene, &law)?;
        eprintln!(
            "{name}: front {} ({} points)",
            ShippedFront::of(&scene, &law).file(),
            front.len()
        );
        let measure_reference = |configuration| {
            stickslip::study::measure(&scene, &law, configuration).map_err(|failed| {
                CliError::VerificationReference {
                    scene: name,
                    source: Box::new(failed),
                }
            })
        };
        let reference = measure_reference(reference_configuration)?;
        let reference_error =
            window_deviation(&reference.tip, &measure_reference(finer_configuration)?.tip);
        eprintln!(
            "{name}: reference {:.2} s, {:.3} um from its finer run",
            reference.seconds,
            reference_error * 1e6
        );
        for &tolerance in tolerances {
            let verified = verify(&scene, &law, tolerance, &front, &reference);
            let case = Case {
                name,
                end: base.time.end,
                reference_error,
                tolerance,
            };
            let (holds, row, line) = match &verified {
                Ok(v) => case.verified(v),
                Err(reason) => case.refused(reason),
            };
            failures += usize::from(!holds);
            println!("{row}");
            csv += &line;
        }
    }
    let path = out.join("auto_verification.csv");
    write_atomically(&path, csv)?;
    println!();
    println!(
        "{failures} of {cases} cases fail; written to {}",
        path.display()
    );
    Ok(())
}

/// One case of `--verify-auto`: a scene, its end time (s), its reference's deviation
/// from the finer run (m) and a tolerance (m).
struct Case<'a> {
    name: &'a str,
    end: f64,
    reference_error: f64,
    tolerance: f64,
}

impl Case<'_> {
    /// Whether the verification holds, its Markdown row and its CSV line.
    fn verified(&self, v: &Verification) -> (bool, String, String) {
        let Case {
            name,
            end,
            reference_error,
            tolerance,
        } = *self;
        let holds = v.holds(tolerance);
        let (cheaper, cheaper_error) = match v.cheaper {
            Some((c, e)) => (c.to_string(), format!("{:.3}", e * 1e6)),
            None => ("(none: the cheapest point)".into(), "-".into()),
        };
        let over = format!("{:?}", v.choice.reach);
        let drift = v
            .choice
            .drift_rate
            .map_or("-".into(), |r| format!("{:.3}", r * 1e3));
        let row = format!(
            "| {name} | {:.3} | {:.3} | {} | {over} | {:.3} | {:.3} | {:.3} | {:.3} | {drift} | {cheaper} | {cheaper_error} | {:.2} | {} to {} | {} |",
            reference_error * 1e6,
            tolerance * 1e6,
            v.choice.configuration,
            v.choice.estimated_error * 1e6,
            v.true_error * 1e6,
            v.true_rms * 1e6,
            v.seconds,
            v.choice.calibration_seconds,
            v.choice.runs,
            v.choice.window,
            if holds { "yes" } else { "NO" }
        );
        let line = format!(
            "{name},{end},{reference_error:e},{tolerance:e},{},{},{:e},{:e},{:e},{:.4},{},{},{},{:.3},{},{},{}\n",
            csv_field(&v.choice.configuration.to_string()),
            csv_field(&over),
            v.choice.estimated_error,
            v.true_error,
            v.true_rms,
            v.seconds,
            v.choice.drift_rate.map_or(String::new(), |r| format!("{r:e}")),
            csv_field(&cheaper),
            v.cheaper.map_or(String::new(), |(_, e)| format!("{e:e}")),
            v.choice.calibration_seconds,
            v.choice.runs,
            v.choice.window,
            holds as u8
        );
        (holds, row, line)
    }

    /// A case whose choice was refused: it fails; its Markdown row and CSV line.
    fn refused(&self, reason: &AutoError) -> (bool, String, String) {
        let (name, end) = (self.name, self.end);
        let (reference_error, tolerance) = (self.reference_error, self.tolerance);
        let row = format!(
            "| {name} | {:.3} | {:.3} | refused: {reason} | | | | | | | | | | | NO |",
            reference_error * 1e6,
            tolerance * 1e6
        );
        let line = format!("{name},{end},{reference_error:e},{tolerance:e},refused,,,,,,,,,,,,0\n");
        (false, row, line)
    }
}
