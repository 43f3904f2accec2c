//! The `simulate` and `static` commands of the `stickslip` binary.
//!
//! The command-line contract (relied on by scripts; extend it, don't rename it):
//! `stickslip simulate [--scene FILE] [--fidelity modal|beam|plane-stress|auto]
//! [--tolerance M] [--friction analytical|exponential|coulomb|neural]
//! [--integrator generalized-alpha|moreau-jean] [--dt S] [--t-end S] [--out FILE.csv]`
//! writes `t,tip_deflection,tip_velocity,friction_force,stick` (SI units, stick as 0/1)
//! and prints a summary.
//! `stickslip static [--fidelity ...] [--element-size M] [--convergence]`.
//!
//! The values of `--fidelity`, `--friction` and `--integrator` are the scene's words
//! (`crate::choice`); `--friction analytical` stays accepted for `exponential`.

use crate::choice::{parser, ChoiceParser};
use crate::CliError;
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use stickslip::run::run_scene;
use stickslip::scene::{CheckedScene, FidelityLevel, FrictionLawKind, Scene, Scheme};
use stickslip::simulation::Sample;
use stickslip::statics::convergence_study;
use stickslip::structure::{euler_bernoulli_tip_deflection, StructuralModel};

/// `--friction`: the scene's laws, plus `analytical`, the command line's name for the
/// exponential law before the values were the scene's words (scripts use it). The
/// external law is refused: its force comes from the StickSlipBeam FMU's inputs.
pub fn friction_parser() -> ChoiceParser<FrictionLawKind> {
    parser::<FrictionLawKind>()
        .alias("analytical", FrictionLawKind::Exponential)
        .refuse(
            FrictionLawKind::External,
            "the external law takes its force from the inputs external.kinetic_force and external.static_limit of the StickSlipBeam FMU, and a command-line run has none",
        )
}

/// Options shared by commands that build a scene: a scene file plus overrides.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Scene file (.toml or .json); missing fields take the paper's values.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Structural model; `auto` also picks the time step and integrator.
    #[arg(long, value_parser = parser::<FidelityLevel>())]
    pub fidelity: Option<FidelityLevel>,
    /// With fidelity auto (`--fidelity auto`, or a scene file's `fidelity.level =
    /// "auto"`): the RMS tip-deflection error allowed over the run (m); it replaces
    /// the scene file's `fidelity.tolerance`.
    #[arg(long, allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// Number of beam elements (beam, and modal from a beam).
    #[arg(long)]
    pub elements: Option<usize>,
    /// Plane-stress element size (m).
    #[arg(long, allow_negative_numbers = true)]
    pub element_size: Option<f64>,
    /// Number of modes of the modal model.
    #[arg(long)]
    pub modes: Option<usize>,
    /// Time step (s).
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// End time (s).
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Time integration scheme.
    #[arg(long, value_parser = parser::<Scheme>())]
    pub integrator: Option<Scheme>,
    /// Generalised-alpha spectral radius at infinity, in [0, 1].
    #[arg(long, allow_negative_numbers = true)]
    pub rho_inf: Option<f64>,
    /// Rayleigh damping ratio applied at the first and third bending frequencies of the
    /// Euler-Bernoulli cantilever.
    #[arg(long, allow_negative_numbers = true)]
    pub damping_ratio: Option<f64>,
    /// Friction law during slip (`analytical` is accepted for `exponential`).
    #[arg(long, value_parser = friction_parser())]
    pub friction: Option<FrictionLawKind>,
    /// Weights file of the neural law (default: the weights shipped with the crate).
    #[arg(long)]
    pub weights: Option<String>,
}

impl SceneArgs {
    /// The scene file (or the paper's scene) with the overrides applied, checked.
    pub fn scene(&self) -> Result<CheckedScene, CliError> {
        let mut scene: Scene = match &self.scene {
            Some(path) => Scene::load(path)?.into_scene(),
            None => Scene::default(),
        };
        if let Some(level) = self.fidelity {
            scene.fidelity.level = level;
        }
        if let Some(n) = self.elements {
            scene.fidelity.beam_elements = n;
        }
        if let Some(s) = self.element_size {
            scene.fidelity.element_size = s;
        }
        if let Some(m) = self.modes {
            scene.fidelity.modes = m;
        }
        if let Some(dt) = self.dt {
            scene.time.step = dt;
        }
        if let Some(t) = self.t_end {
            scene.time.end = t;
        }
        if let Some(s) = self.integrator {
            scene.integrator.scheme = s;
        }
        if let Some(r) = self.rho_inf {
            scene.integrator.rho_inf = r;
        }
        if let Some(f) = self.friction {
            scene.friction.law = f;
        }
        if let Some(w) = &self.weights {
            scene.friction.weights = Some(w.clone());
        }
        // Before the damping: it checks the scene, and a scene with fidelity auto is
        // valid only with its tolerance.
        let auto_tolerance = self.auto_tolerance(&mut scene)?;
        if let Some(zeta) = self.damping_ratio {
            // At the first and third cantilever frequencies (the same numbers
            // `stickslip estimates` prints).
            let checked = scene.clone().check()?;
            if !(zeta.is_finite() && zeta >= 0.0) {
                return Err(CliError::DampingRatio(zeta));
            }
            scene.damping = stickslip::stability::rayleigh_at_modes_1_and_3(&checked, zeta);
        }
        let Some(tolerance) = auto_tolerance else {
            return Ok(scene.check()?);
        };
        let front = stickslip::auto::paper_front()?;
        let (resolved, choice) = stickslip::auto::resolve(scene, &front)?;
        if let Some(choice) = &choice {
            eprintln!("{}", stickslip::auto::describe(choice, tolerance));
        }
        Ok(resolved.check()?)
    }

    /// With fidelity auto (from `--fidelity auto` or the scene file): puts `--tolerance`
    /// into the scene, refuses the flags whose values auto chooses, and returns the
    /// tolerance (m). Without auto: None, and `--tolerance` is refused.
    fn auto_tolerance(&self, scene: &mut Scene) -> Result<Option<f64>, CliError> {
        if scene.fidelity.level != FidelityLevel::Auto {
            if self.tolerance.is_some() {
                return Err(CliError::ToleranceWithoutAuto);
            }
            return Ok(None);
        }
        let by = if self.fidelity == Some(FidelityLevel::Auto) {
            "--fidelity auto"
        } else {
            "the scene's fidelity.level = auto"
        };
        if let Some(tolerance) = self.tolerance {
            scene.fidelity.tolerance = Some(tolerance);
        }
        let Some(tolerance) = scene.fidelity.tolerance else {
            return Err(CliError::AutoWithoutTolerance { by });
        };
        let chosen_by_auto = [
            ("--elements", self.elements.is_some()),
            ("--element-size", self.element_size.is_some()),
            ("--modes", self.modes.is_some()),
            ("--dt", self.dt.is_some()),
            ("--integrator", self.integrator.is_some()),
        ];
        if let Some(&(flag, _)) = chosen_by_auto.iter().find(|(_, given)| *given) {
            return Err(CliError::ChosenByAuto { flag, by });
        }
        Ok(Some(tolerance))
    }
}

/// Arguments of `stickslip simulate`.
#[derive(Args, Debug, Clone)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// CSV output: t,tip_deflection,tip_velocity,friction_force,stick (SI units).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write every N-th step to the CSV.
    #[arg(long, default_value_t = 1)]
    pub every: usize,
    /// Also write the summary (and the transitions) as JSON.
    #[arg(long)]
    pub summary_json: Option<PathBuf>,
}

/// Writes samples as the contract's CSV.
pub fn write_csv(path: &PathBuf, samples: &[Sample]) -> Result<(), CliError> {
    let io = |source: std::io::Error| CliError::Output {
        path: path.clone(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut w = std::io::BufWriter::new(file);
    writeln!(w, "t,tip_deflection,tip_velocity,friction_force,stick").map_err(io)?;
    for s in samples {
        writeln!(
            w,
            "{:.10e},{:.10e},{:.10e},{:.10e},{}",
            s.time, s.tip_deflection, s.tip_velocity, s.friction_force, s.stick as u8
        )
        .map_err(io)?;
    }
    w.flush().map_err(io)
}

/// Writes an output file of `simulate`, `static` or `study`.
fn write(path: &std::path::Path, contents: impl AsRef<[u8]>) -> Result<(), CliError> {
    std::fs::write(path, contents).map_err(|source| CliError::Output {
        path: path.to_path_buf(),
        source,
    })
}

/// `stickslip simulate`.
pub fn simulate(args: &SimulateArgs) -> Result<(), CliError> {
    let scene = args.scene.scene()?;
    let end = scene.time.end;
    // The summary is computed on every step; decimation applies to the CSV only.
    let run = run_scene(scene, 1)?;
    if let Some(path) = &args.out {
        let every = args.every.max(1);
        let kept: Vec<Sample> = run.samples.iter().step_by(every).copied().collect();
        write_csv(path, &kept)?;
    }
    if let Some(path) = &args.summary_json {
        let text = serde_json::to_string_pretty(&run.summary).map_err(|source| CliError::Json {
            path: path.clone(),
            source,
        })?;
        write(path, text)?;
    }
    println!("{}", run.label);
    print!("{}", run.summary.report());
    println!(
        "wall time               {:.3} s ({:.1}x real time)",
        run.seconds,
        end / run.seconds
    );
    Ok(())
}

/// Arguments of `stickslip static`.
#[derive(Args, Debug, Clone)]
pub struct StaticArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Tip load P (N).
    #[arg(long, default_value_t = 50.0, allow_negative_numbers = true)]
    pub load: f64,
    /// Print the mesh-convergence table of the plane-stress model (the paper's Fig. 1b).
    #[arg(long)]
    pub convergence: bool,
    /// Write the convergence table as CSV.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `stickslip static`.
pub fn static_check(args: &StaticArgs) -> Result<(), CliError> {
    let scene = args.scene.scene()?;
    if !(args.load.is_finite() && args.load != 0.0) {
        return Err(CliError::Load(args.load));
    }
    let eb = euler_bernoulli_tip_deflection(&scene, args.load);
    if args.convergence {
        let sizes = [0.16, 0.08, 0.04, 0.02, 0.01, 0.005];
        let rows = convergence_study(&scene, args.load, &sizes)?;
        println!(
            "plane-stress Q8, tip load {} N, delta_EB = 4 P L^3 / (E h^3) = {:.6} mm",
            args.load,
            eb * 1e3
        );
        println!(
            "{:<13} {:>10} {:>7} {:>7} {:>14} {:>12} {:>12}",
            "clamp", "size (m)", "nodes", "dofs", "delta (mm)", "err EB", "err Timo"
        );
        for r in &rows {
            println!(
                "{:<13} {:>10.4} {:>7} {:>7} {:>14.9} {:>11.4}% {:>11.4}%",
                r.clamp,
                r.element_size,
                r.nodes,
                r.dofs,
                r.deflection * 1e3,
                100.0 * r.error_euler_bernoulli,
                100.0 * r.error_timoshenko
            );
        }
        if let Some(path) = &args.out {
            let mut text = String::from(
                "clamp,element_size,nodes,dofs,deflection,error_euler_bernoulli,error_timoshenko\n",
            );
            for r in &rows {
                text += &format!(
                    "{},{},{},{},{:.12e},{:.6e},{:.6e}\n",
                    r.clamp,
                    r.element_size,
                    r.nodes,
                    r.dofs,
                    r.deflection,
                    r.error_euler_bernoulli,
                    r.error_timoshenko
                );
            }
            write(path, text)?;
        }
        return Ok(());
    }
    let model = StructuralModel::build(&scene)?;
    let d = model.static_tip_deflection(args.load)?;
    println!("{}", model.label);
    println!("tip load                {} N", args.load);
    println!("tip deflection          {:.9} mm", d * 1e3);
    println!(
        "Euler-Bernoulli         {:.9} mm (4 P L^3 / (E h^3))",
        eb * 1e3
    );
    println!(
        "relative error          {:.5} %",
        100.0 * (d - eb).abs() / eb.abs()
    );
    Ok(())
}

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
    /// Time steps (s); each must divide 1 ms.
    #[arg(long, value_delimiter = ',')]
    pub dts: Option<Vec<f64>>,
    /// Integrators.
    #[arg(long, value_parser = parser::<Scheme>(), value_delimiter = ',')]
    pub integrators: Option<Vec<Scheme>>,
    /// Output folder: study.csv (every run) and front.json (the Pareto front).
    #[arg(long, default_value = "out/study")]
    pub out: PathBuf,
    /// Also write the front to this file (the `auto` fidelity reads
    /// data/pareto_front.json).
    #[arg(long)]
    pub write_front: Option<PathBuf>,
    /// After the study, check `fidelity = auto` (with the shipped front) at these
    /// tolerances (m) on four scenes, each against its own reference run.
    #[arg(long, value_delimiter = ',')]
    pub verify_auto: Option<Vec<f64>>,
}

/// `stickslip study`: the grid, the reference, the CSV and the front.
pub fn study(args: &StudyArgs) -> Result<(), CliError> {
    use stickslip::study::{
        csv_line, front, front_points, mark_pareto_front, measure, Errors, Grid, Row, CSV_HEADER,
    };
    let mut scene = match &args.scene {
        Some(path) => Scene::load(path)?.into_scene(),
        None => Scene::default(),
    };
    if let Some(t) = args.t_end {
        scene.time.end = t;
    }
    let full = Grid::full();
    let grid = Grid {
        modes: args.modes.clone().unwrap_or(full.modes),
        beam_elements: args.elements.clone().unwrap_or(full.beam_elements),
        element_sizes: args.element_sizes.clone().unwrap_or(full.element_sizes),
        time_steps: args.dts.clone().unwrap_or(full.time_steps),
        schemes: match &args.integrators {
            Some(list) => list.clone(),
            None => full.schemes,
        },
    };
    let reference_configuration = grid.finest().ok_or(CliError::EmptyGrid)?;
    let configurations = grid.configurations();
    std::fs::create_dir_all(&args.out).map_err(|source| CliError::Output {
        path: args.out.clone(),
        source,
    })?;
    eprintln!(
        "study: {} configurations, end time {} s; reference {reference_configuration}",
        configurations.len(),
        scene.time.end
    );
    let reference = measure(&scene, reference_configuration)
        .map_err(|failed| CliError::Reference(Box::new(failed)))?;
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for (k, configuration) in configurations.iter().enumerate() {
        let measured = if *configuration == reference_configuration {
            Ok(reference.clone())
        } else {
            measure(&scene, *configuration)
        };
        match measured {
            Ok(measured) => {
                let errors = Errors::between(&measured, &reference);
                eprintln!(
                    "[{}/{}] {configuration}: {:.3} s, RMS error {:.3e} m",
                    k + 1,
                    configurations.len(),
                    measured.seconds,
                    errors.rms
                );
                rows.push(Row {
                    measured,
                    errors,
                    on_front: false,
                });
            }
            Err(failed) => {
                eprintln!(
                    "[{}/{}] {configuration}: failed: {}",
                    k + 1,
                    configurations.len(),
                    failed.reason
                );
                failures.push(failed);
            }
        }
    }
    // The reference is exact by definition; it stays off the front, whose last point is
    // then the best run that can be compared with something better.
    rows.retain(|r| r.measured.configuration != reference_configuration);
    mark_pareto_front(&mut rows);
    let csv_path = args.out.join("study.csv");
    let mut csv = String::from(CSV_HEADER);
    csv.push('\n');
    for row in &rows {
        csv += &csv_line(row, scene.time.end);
        csv.push('\n');
    }
    write(&csv_path, csv)?;
    let points = front_points(&rows);
    let front_path = args.out.join("front.json");
    let json = serde_json::to_string_pretty(&points).map_err(|source| CliError::Json {
        path: front_path.clone(),
        source,
    })?;
    for path in std::iter::once(&front_path).chain(args.write_front.as_ref()) {
        write(path, &json)?;
    }

    println!(
        "reference: {reference_configuration}: {} dofs, {:.2} s",
        reference.dofs, reference.seconds
    );
    println!();
    println!("Pareto front (RMS tip-deflection error against wall time), cheapest first:");
    println!();
    println!("| configuration | dofs | wall (s) | x real time | breakaway (ms) | 1st slip (ms) | period (ms) | corridor (um) | RMS (um) |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let ms = |v: Option<f64>| v.map_or("-".into(), |v| format!("{:.3}", v * 1e3));
    for row in front(&rows) {
        let e = &row.errors;
        println!(
            "| {} | {} | {:.4} | {:.0} | {} | {} | {} | {} | {:.3} |",
            row.measured.configuration,
            row.measured.dofs,
            row.measured.seconds,
            scene.time.end / row.measured.seconds,
            ms(e.breakaway),
            ms(e.first_slip_duration),
            ms(e.period),
            e.corridor.map_or("-".into(), |v| format!("{:.3}", v * 1e6)),
            e.rms * 1e6
        );
    }
    println!();
    println!(
        "{} runs in {}, {} on the front, {} failed; front in {}",
        rows.len() + 1,
        csv_path.display(),
        points.len(),
        failures.len(),
        front_path.display()
    );
    for f in &failures {
        println!("failed: {}: {}", f.configuration, f.reason);
    }
    if let Some(tolerances) = &args.verify_auto {
        verify_auto(&scene, tolerances, reference_configuration, &args.out)?;
    }
    Ok(())
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
    reference_configuration: stickslip::study::Configuration,
    out: &std::path::Path,
) -> Result<(), CliError> {
    use stickslip::auto::{paper_front, verification_scenes, verify};
    let front = paper_front()?;
    println!();
    println!(
        "fidelity = auto on four scenes (shipped front, {} points); true error against each scene's {reference_configuration}, end time {} s:",
        front.len(),
        base.time.end
    );
    println!();
    println!("| scene | tolerance (um) | choice | estimated (um) | true (um) | next cheaper | its true error (um) | calibration (s) | holds |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut csv = String::from(
        "scene,tolerance_m,choice,estimated_m,true_m,cheaper,cheaper_true_m,calibration_s,holds\n",
    );
    let mut failures = 0;
    for (name, mut scene) in verification_scenes() {
        scene.time.end = base.time.end;
        let reference =
            stickslip::study::measure(&scene, reference_configuration).map_err(|failed| {
                CliError::VerificationReference {
                    scene: name,
                    source: Box::new(failed),
                }
            })?;
        for &tolerance in tolerances {
            match verify(&scene, tolerance, &front, &reference) {
                Ok(v) => {
                    let holds = v.holds(tolerance);
                    failures += usize::from(!holds);
                    let (cheaper, cheaper_error) = match v.cheaper {
                        Some((c, e)) => (c.to_string(), format!("{:.3}", e * 1e6)),
                        None => ("(none: the cheapest point)".into(), "-".into()),
                    };
                    println!(
                        "| {name} | {:.3} | {} | {:.3} | {:.3} | {cheaper} | {cheaper_error} | {:.2} | {} |",
                        tolerance * 1e6,
                        v.choice.configuration,
                        v.choice.estimated_error * 1e6,
                        v.true_error * 1e6,
                        v.choice.calibration_seconds,
                        if holds { "yes" } else { "NO" }
                    );
                    csv += &format!(
                        "{name},{tolerance:e},{},{:e},{:e},{},{},{:.3},{}\n",
                        csv_field(&v.choice.configuration.to_string()),
                        v.choice.estimated_error,
                        v.true_error,
                        csv_field(&cheaper),
                        v.cheaper.map_or(String::new(), |(_, e)| format!("{e:e}")),
                        v.choice.calibration_seconds,
                        holds as u8
                    );
                }
                Err(reason) => {
                    failures += 1;
                    println!(
                        "| {name} | {:.3} | refused: {reason} | | | | | | NO |",
                        tolerance * 1e6
                    );
                    csv += &format!("{name},{tolerance:e},refused,,,,,,0\n");
                }
            }
        }
    }
    let path = out.join("auto_verification.csv");
    write(&path, csv)?;
    println!();
    println!(
        "{failures} of {} cases fail; written to {}",
        tolerances.len() * 4,
        path.display()
    );
    Ok(())
}
