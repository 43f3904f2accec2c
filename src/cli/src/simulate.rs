//! The `simulate` and `static` commands of the `stickslip` binary.
//!
//! The command-line contract (relied on by scripts; extend it, don't rename it):
//! `stickslip simulate [--scene FILE] [--fidelity LEVEL] [--tolerance M]
//! [--friction LAW] [--integrator SCHEME] [--dt S] [--t-end S] [--out FILE.csv]`
//! writes `t,tip_deflection,tip_velocity,friction_force,stick` (SI units, stick as 0/1),
//! followed, for a friction law with state, by one column per state variable of the law
//! under its name (`bristle_deflection` (m) for LuGre, `state_theta` (s) for
//! rate-and-state, `state_psi` (1) for the learned law with memory:
//! `stickslip::friction::state::STATE_VARIABLES`), then, for a scene whose
//! `[structure]` names sensors, two columns per sensor: `NAME` (m) and `NAME_velocity`
//! (m/s), in the section's order; and prints a summary.
//! `stickslip static [--fidelity LEVEL] [--element-size M] [--convergence]`; with a
//! `[structure]`, the structure's static response to `--load` at its contact DOF: the
//! contact's deflection and compliance and each sensor's reading
//! (`stickslip::linear_structure::estimates::static_response`).
//!
//! LEVEL, LAW and SCHEME are the words of the scene's `fidelity.level`, `friction.law`
//! and `integrator.scheme` (`stickslip simulate --help` lists them); `--friction` also
//! takes `analytical` for `exponential` (`crate::scene_args`).

use crate::error::CliError;
use crate::scene_args::SceneArgs;
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use stickslip::files::{write_atomically, Outputs};
use stickslip::friction::state::STATE_VARIABLES;
use stickslip::linear_structure::estimates::static_response;
use stickslip::run::run_scene;
use stickslip::simulation::{Sample, SensorReading};
use stickslip::statics::convergence_study;
use stickslip::structure::{euler_bernoulli_tip_deflection, StructuralModel};
use stickslip::user_structure::Sensor;

/// Arguments of `stickslip simulate`.
#[derive(Args, Debug, Clone)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// CSV output: t,tip_deflection,tip_velocity,friction_force,stick (SI units), and
    /// for a law with state its state variables (bristle_deflection, state_theta or
    /// state_psi), then each [structure] sensor's NAME and NAME_velocity.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write every N-th step to the CSV.
    #[arg(long, default_value_t = 1)]
    pub every: usize,
    /// Also write the summary (and the transitions) as JSON.
    #[arg(long)]
    pub summary_json: Option<PathBuf>,
}

/// The columns every CSV of `simulate --out` starts with.
pub const FIXED_COLUMNS: [&str; 5] = [
    "t",
    "tip_deflection",
    "tip_velocity",
    "friction_force",
    "stick",
];

/// The first sensor output (`NAME` or `NAME_velocity`) that would repeat a column of the
/// CSV: a file with two columns of one name is read by most tools as one of them only.
pub fn sensor_column_clash(sensors: &[Sensor]) -> Option<String> {
    let taken = |name: &str| {
        FIXED_COLUMNS.contains(&name) || STATE_VARIABLES.iter().any(|v| v.name == name)
    };
    sensors
        .iter()
        .flat_map(|s| [s.name.clone(), s.velocity_name()])
        .find(|name| taken(name))
}

/// Writes samples as the contract's CSV, with a column for each of the law's state
/// variables `law_state` (indices in `STATE_VARIABLES` and `Sample::law_state`, as
/// `run::Run::law_state_slots` gives them; none for a memoryless law, whose file is
/// then the five columns it always was), then each sensor's displacement and velocity
/// (`readings` holds one row per sample, or is empty without sensors).
pub fn write_csv(
    w: &mut dyn Write,
    samples: &[Sample],
    law_state: &[usize],
    (sensors, readings): (&[Sensor], &[Vec<SensorReading>]),
) -> std::io::Result<()> {
    write!(w, "{}", FIXED_COLUMNS.join(","))?;
    for &k in law_state {
        write!(w, ",{}", STATE_VARIABLES[k].name)?;
    }
    for sensor in sensors {
        write!(w, ",{},{}", sensor.name, sensor.velocity_name())?;
    }
    writeln!(w)?;
    for (n, s) in samples.iter().enumerate() {
        write!(
            w,
            "{:.10e},{:.10e},{:.10e},{:.10e},{}",
            s.time, s.tip_deflection, s.tip_velocity, s.friction_force, s.stick as u8
        )?;
        for &k in law_state {
            write!(w, ",{:.10e}", s.law_state[k])?;
        }
        for r in readings.get(n).into_iter().flatten() {
            write!(w, ",{:.10e},{:.10e}", r.displacement, r.velocity)?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// `stickslip simulate`.
pub fn simulate(args: &SimulateArgs) -> Result<(), CliError> {
    let (scene, law) = args.scene.scene_and_law()?;
    let end = scene.time.end;
    let sensors: Vec<Sensor> = scene
        .structure
        .as_ref()
        .map(|s| s.sensors.clone())
        .unwrap_or_default();
    // Before the run, so that a long run is not lost to a file it cannot write.
    if args.out.is_some() {
        if let Some(name) = sensor_column_clash(&sensors) {
            return Err(CliError::SensorNamesAColumn(name));
        }
    }
    // The summary is computed on every step; decimation applies to the CSV only.
    let run = run_scene(scene, &law, 1)?;
    // Both files or neither: a summary without its samples would be taken for a run.
    let mut outputs = Outputs::new();
    if let Some(path) = &args.out {
        let every = args.every.max(1);
        let kept: Vec<Sample> = run.samples.iter().step_by(every).copied().collect();
        let readings: Vec<Vec<SensorReading>> =
            run.sensors.iter().step_by(every).cloned().collect();
        outputs.add_with(path, |w| {
            write_csv(w, &kept, &run.law_state_slots, (&sensors, &readings))
        })?;
    }
    if let Some(path) = &args.summary_json {
        let text = serde_json::to_string_pretty(&run.summary).map_err(|source| CliError::Json {
            path: path.clone(),
            source,
        })?;
        outputs.add(path, text)?;
    }
    outputs.commit()?;
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
    if let Some(section) = &scene.structure {
        if args.convergence || args.out.is_some() {
            return Err(CliError::ConvergenceWithStructure);
        }
        let r = static_response(section, args.load)?;
        println!("{}", r.label);
        println!(
            "contact load            {} (N at the contact DOF, in its direction)",
            r.load
        );
        // SI units throughout: a DOF may be a rotation (rad, N m).
        println!("contact deflection      {:.9e} m", r.contact);
        println!("contact compliance      {:.9e} m/N", r.contact / r.load);
        for (name, value) in &r.sensors {
            println!("sensor {name:<16} {value:.9e} m");
        }
        return Ok(());
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
            write_atomically(path, text)?;
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
