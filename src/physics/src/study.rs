//! The speed-accuracy study: one scene run over a grid of fidelity levels, time steps,
//! integrators and, for the neural law, ways of evaluating it (`friction.inference`),
//! each run timed and compared with a converged reference.
//!
//! For every configuration the study records the wall time (model build plus stepping,
//! as [`crate::run::run_scene`] measures it, runs one after the other so that no two
//! compete for a core) and these errors against the reference run:
//! - breakaway time, first major-slip duration and stick-slip period (s), from
//!   [`Summary`];
//! - deflection corridor after breakaway (m): the larger of the differences of its
//!   minimum and of its maximum;
//! - RMS of the tip-deflection difference over the whole run (m), on a 1 ms grid
//!   that every time step of the grid divides.
//!
//! The reference is the most expensive configuration of the grid unless given: by
//! default the finest plane-stress mesh (0.005 m) at the smallest step (1e-5 s) with
//! generalised-alpha, with the scene's own inference (exact by default). A configuration
//! is on the Pareto front when no other one is both faster and more accurate (in RMS).
//! The wall time does not include building the friction law (parsing the network,
//! tabulating it: 1 to 25 ms for the shipped networks), as [`run_scene`] times it.

use crate::choice::Choice;
use crate::law_source::LawSource;
use crate::metrics::Summary;
use crate::run::{run_scene, RunError};
use crate::scene::{CheckedScene, FidelityLevel, Inference, ModalBasis, Scene, SceneError, Scheme};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The grid of the tip-deflection comparison (s): every time step of a study divides it.
pub const COMPARISON_INTERVAL: f64 = 1e-3;

/// The structural resolution of one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "level")]
pub enum Resolution {
    /// Modal reduction of the scene's beam (100 elements unless the scene says
    /// otherwise) with this many modes (plus the static correction).
    Modal { modes: usize },
    /// Euler-Bernoulli beam with this many elements.
    Beam { elements: usize },
    /// Plane-stress Q8 mesh with this target element size (m).
    PlaneStress { element_size: f64 },
    /// Modal reduction of the plane-stress mesh of this element size (m) with this many
    /// modes (plus the static correction): the scene's `fidelity.level = modal` with
    /// `fidelity.modal_basis = plane-stress`. Its modes come from shift-invert Lanczos
    /// (`modal::lanczos_modes`).
    PlaneStressModal { element_size: f64, modes: usize },
}

impl Resolution {
    pub fn level(&self) -> FidelityLevel {
        match self {
            Resolution::Modal { .. } => FidelityLevel::Modal,
            Resolution::Beam { .. } => FidelityLevel::Beam,
            Resolution::PlaneStress { .. } => FidelityLevel::PlaneStress,
            Resolution::PlaneStressModal { .. } => FidelityLevel::Modal,
        }
    }

    /// Whether the model is the plane-stress continuum (the full mesh or a modal basis
    /// of it) rather than Euler-Bernoulli beam theory: only the continuum has shear and
    /// the clamp's elasticity, the model error that beam-theory points share.
    pub fn is_continuum(&self) -> bool {
        matches!(
            self,
            Resolution::PlaneStress { .. } | Resolution::PlaneStressModal { .. }
        )
    }

    /// The resolution's kind as study.csv's `level` column writes it: the fidelity
    /// level's name, except `plane-stress-modal` for the modal level on the mesh.
    pub fn kind(&self) -> &'static str {
        match self {
            Resolution::PlaneStressModal { .. } => "plane-stress-modal",
            other => other.level().name(),
        }
    }
}

impl fmt::Display for Resolution {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Resolution::Modal { modes } => write!(f, "modal {modes} modes"),
            Resolution::Beam { elements } => write!(f, "beam {elements} el."),
            Resolution::PlaneStress { element_size } => {
                write!(f, "plane stress {element_size} m")
            }
            Resolution::PlaneStressModal {
                element_size,
                modes,
            } => write!(f, "modal {modes} modes of plane stress {element_size} m"),
        }
    }
}

/// One point of the grid: resolution, time step, integrator and the evaluation of a
/// neural law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Configuration {
    pub resolution: Resolution,
    /// Time step (s).
    pub dt: f64,
    pub scheme: Scheme,
    /// `friction.inference`; None keeps the scene's (the `auto` fidelity's front has
    /// none, so that its choice leaves the inference alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inference: Option<Inference>,
}

impl Configuration {
    /// `scene` with this configuration's fidelity, time step, integrator and inference
    /// (if it has one); every other field (geometry, material, loading, friction,
    /// damping, end time) kept.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut scene = scene.clone();
        scene.fidelity.level = self.resolution.level();
        match self.resolution {
            Resolution::Modal { modes } => {
                scene.fidelity.modes = modes;
                scene.fidelity.modal_basis = ModalBasis::Beam;
            }
            Resolution::Beam { elements } => scene.fidelity.beam_elements = elements,
            Resolution::PlaneStress { element_size } => scene.fidelity.element_size = element_size,
            Resolution::PlaneStressModal {
                element_size,
                modes,
            } => {
                scene.fidelity.modes = modes;
                scene.fidelity.element_size = element_size;
                scene.fidelity.modal_basis = ModalBasis::PlaneStress;
            }
        }
        scene.time.step = self.dt;
        scene.integrator.scheme = self.scheme;
        if let Some(inference) = self.inference {
            scene.friction.inference = inference;
        }
        scene
    }

    pub fn scheme_name(&self) -> &'static str {
        self.scheme.name()
    }
}

impl fmt::Display for Configuration {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}, dt {:e} s, {}",
            self.resolution,
            self.dt,
            self.scheme_name()
        )?;
        match self.inference {
            Some(inference) => write!(f, ", {} inference", inference.name()),
            None => Ok(()),
        }
    }
}

/// The axes of a study grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub modes: Vec<usize>,
    pub beam_elements: Vec<usize>,
    pub element_sizes: Vec<f64>,
    /// Modal reductions of the plane-stress mesh: (element size (m), modes) pairs.
    pub plane_stress_modal: Vec<(f64, usize)>,
    pub time_steps: Vec<f64>,
    pub schemes: Vec<Scheme>,
    /// Evaluations of a neural law; empty: the scene's own.
    pub inferences: Vec<Inference>,
}

impl Grid {
    /// The issue's grid: modal 1..20 modes, beam 5..200 elements, plane stress
    /// 0.08..0.005 m, time steps 1e-3..1e-5 s, both integrators; and (issue 17) the
    /// modal bases of the mesh that reached the front (docs/speed-accuracy.md): 5 and 10
    /// modes of the 0.02 m mesh, 10 of the 0.01 m one, 10 and 20 of the 0.005 m one.
    pub fn full() -> Self {
        Self {
            modes: vec![1, 2, 3, 5, 10, 20],
            beam_elements: vec![5, 10, 20, 50, 100, 200],
            element_sizes: vec![0.08, 0.04, 0.02, 0.01, 0.005],
            plane_stress_modal: vec![(0.02, 5), (0.02, 10), (0.01, 10), (0.005, 10), (0.005, 20)],
            time_steps: vec![1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5],
            schemes: vec![Scheme::GeneralizedAlpha, Scheme::MoreauJean],
            inferences: Vec::new(),
        }
    }

    /// Every configuration, cheapest resolutions first.
    pub fn configurations(&self) -> Vec<Configuration> {
        let resolutions = self
            .modes
            .iter()
            .map(|&modes| Resolution::Modal { modes })
            .chain(
                self.beam_elements
                    .iter()
                    .map(|&elements| Resolution::Beam { elements }),
            )
            .chain(
                self.plane_stress_modal
                    .iter()
                    .map(|&(element_size, modes)| Resolution::PlaneStressModal {
                        element_size,
                        modes,
                    }),
            )
            .chain(
                self.element_sizes
                    .iter()
                    .map(|&element_size| Resolution::PlaneStress { element_size }),
            );
        let inferences: Vec<Option<Inference>> = if self.inferences.is_empty() {
            vec![None]
        } else {
            self.inferences.iter().copied().map(Some).collect()
        };
        let mut out = Vec::new();
        for resolution in resolutions {
            for &dt in &self.time_steps {
                for &scheme in &self.schemes {
                    for &inference in &inferences {
                        out.push(Configuration {
                            resolution,
                            dt,
                            scheme,
                            inference,
                        });
                    }
                }
            }
        }
        out
    }

    /// The default reference: the finest mesh (or, without plane stress, the richest
    /// modal basis of the finest mesh; without either, the finest beam) at the smallest
    /// step, with generalised-alpha and the exact network if the
    /// grid has an inference axis.
    pub fn finest(&self) -> Option<Configuration> {
        let dt = self.time_steps.iter().copied().fold(f64::NAN, f64::min);
        let resolution = if let Some(size) = self.element_sizes.iter().copied().reduce(f64::min) {
            Resolution::PlaneStress { element_size: size }
        } else if let Some(&(element_size, modes)) = self
            .plane_stress_modal
            .iter()
            .min_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
        {
            // A basis of the mesh is closer to the continuum than any beam; without the
            // full mesh in the grid it is the reference (`study --verify-auto` uses one:
            // 0.035 um RMS from the full 0.005 m mesh on the paper scene, at 1/150 of
            // its cost).
            Resolution::PlaneStressModal {
                element_size,
                modes,
            }
        } else if let Some(&elements) = self.beam_elements.iter().max() {
            Resolution::Beam { elements }
        } else {
            Resolution::Modal {
                modes: *self.modes.iter().max()?,
            }
        };
        dt.is_finite().then_some(Configuration {
            resolution,
            dt,
            scheme: Scheme::GeneralizedAlpha,
            inference: (!self.inferences.is_empty()).then_some(Inference::Exact),
        })
    }
}

/// What one run gives the comparison.
#[derive(Clone, Debug)]
pub struct Measured {
    pub configuration: Configuration,
    pub dofs: usize,
    /// Wall time of model build and stepping (s).
    pub seconds: f64,
    pub summary: Summary,
    /// Tip deflection at k * [`COMPARISON_INTERVAL`], k = 0, 1, ... (m).
    pub tip: Vec<f64>,
}

/// Why a configuration could not run.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// The scene with this configuration applied does not pass [`Scene::check`].
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The time step does not divide [`COMPARISON_INTERVAL`], so that the run's samples
    /// would miss the comparison grid.
    #[error("time step {dt} s does not divide the comparison interval {COMPARISON_INTERVAL} s")]
    Interval { dt: f64 },
    /// The friction law could not be built or the simulation failed.
    #[error(transparent)]
    Run(#[from] RunError),
}

/// A configuration that could not run, and why.
#[derive(Debug, thiserror::Error)]
#[error("{configuration}: {reason}")]
pub struct Failed {
    /// Boxed so that the error stays small (clippy's result_large_err: it travels in
    /// `auto::AutoError` through every `Result` of the selection).
    pub configuration: Box<Configuration>,
    #[source]
    pub reason: MeasureError,
}

/// Runs `configuration` on `scene` (checked) under `law` (the scene's, resolved once for
/// every configuration; a configuration's inference replaces the law's), timing it.
pub fn measure(
    scene: &Scene,
    law: &LawSource,
    configuration: Configuration,
) -> Result<Measured, Failed> {
    let failed = |reason: MeasureError| Failed {
        configuration: Box::new(configuration),
        reason,
    };
    let checked: CheckedScene = configuration
        .apply(scene)
        .check()
        .map_err(|e| failed(e.into()))?;
    let every = COMPARISON_INTERVAL / configuration.dt;
    if (every - every.round()).abs() > 1e-9 * every || every.round() < 1.0 {
        return Err(failed(MeasureError::Interval {
            dt: configuration.dt,
        }));
    }
    let every = every.round() as usize;
    // Every step is kept so that the summary (corridor, slip detection) does not depend
    // on the time step through its sampling.
    let law = law.with_inference(checked.friction.inference);
    let run = run_scene(checked, &law, 1).map_err(|e| failed(e.into()))?;
    let tip = run
        .samples
        .iter()
        .step_by(every)
        .map(|s| s.tip_deflection)
        .collect();
    Ok(Measured {
        configuration,
        dofs: run.dofs,
        seconds: run.seconds,
        summary: run.summary,
        tip,
    })
}

/// Errors of a run against the reference; `None` where either run lacks the metric
/// (no breakaway, fewer than two major slips ...).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Errors {
    /// |breakaway - reference| (s).
    pub breakaway: Option<f64>,
    /// |first major-slip duration - reference| (s).
    pub first_slip_duration: Option<f64>,
    /// |stick-slip period - reference| (s).
    pub period: Option<f64>,
    /// max(|min - min_ref|, |max - max_ref|) of the corridor after breakaway (m).
    pub corridor: Option<f64>,
    /// RMS of the tip-deflection difference over the run (m).
    pub rms: f64,
}

fn difference(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    Some((a? - b?).abs())
}

/// RMS of the difference of two tip series on the same grid (m).
pub fn rms_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return f64::NAN;
    }
    let sum: f64 = a[..n]
        .iter()
        .zip(&b[..n])
        .map(|(x, y)| (x - y).powi(2))
        .sum();
    (sum / n as f64).sqrt()
}

impl Errors {
    pub fn between(run: &Measured, reference: &Measured) -> Self {
        let (s, r) = (&run.summary, &reference.summary);
        let first_duration = |s: &Summary| s.major_slips.first().and_then(|m| m.duration);
        let corridor = match (s.corridor, r.corridor) {
            (Some((lo, hi)), Some((rlo, rhi))) => Some((lo - rlo).abs().max((hi - rhi).abs())),
            _ => None,
        };
        Self {
            breakaway: difference(s.breakaway, r.breakaway),
            first_slip_duration: difference(first_duration(s), first_duration(r)),
            period: difference(s.period, r.period),
            corridor,
            rms: rms_difference(&run.tip, &reference.tip),
        }
    }
}

/// One row of the study.
#[derive(Clone, Debug)]
pub struct Row {
    pub measured: Measured,
    pub errors: Errors,
    pub on_front: bool,
}

/// Marks the rows that no other row beats in both wall time and RMS error.
pub fn mark_pareto_front(rows: &mut [Row]) {
    let points: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.measured.seconds, r.errors.rms))
        .collect();
    for (k, row) in rows.iter_mut().enumerate() {
        let (t, e) = points[k];
        row.on_front = e.is_finite()
            && !points
                .iter()
                .enumerate()
                .any(|(j, &(tj, ej))| j != k && tj <= t && ej <= e && (tj < t || ej < e));
    }
}

/// The front, cheapest first (so error decreases along it).
pub fn front(rows: &[Row]) -> Vec<&Row> {
    let mut front: Vec<&Row> = rows.iter().filter(|r| r.on_front).collect();
    front.sort_by(|a, b| a.measured.seconds.total_cmp(&b.measured.seconds));
    front
}

/// The CSV header of [`csv_line`].
pub const CSV_HEADER: &str = "level,modes,beam_elements,element_size_m,dt_s,integrator,inference,dofs,wall_s,realtime_factor,err_breakaway_s,err_first_slip_duration_s,err_period_s,err_corridor_m,err_rms_m,pareto";

/// One CSV line of a row; missing values are empty fields.
pub fn csv_line(row: &Row, end_time: f64) -> String {
    let c = &row.measured.configuration;
    let level = c.resolution.kind();
    let (modes, elements, size) = match c.resolution {
        Resolution::Modal { modes } => (modes.to_string(), String::new(), String::new()),
        Resolution::Beam { elements } => (String::new(), elements.to_string(), String::new()),
        Resolution::PlaneStress { element_size } => {
            (String::new(), String::new(), element_size.to_string())
        }
        Resolution::PlaneStressModal {
            element_size,
            modes,
        } => (modes.to_string(), String::new(), element_size.to_string()),
    };
    let opt = |v: Option<f64>| v.map(|v| format!("{v:.6e}")).unwrap_or_default();
    let e = &row.errors;
    format!(
        "{level},{modes},{elements},{size},{:e},{},{},{},{:.6e},{:.3},{},{},{},{},{:.6e},{}",
        c.dt,
        c.scheme_name(),
        c.inference.map_or("", Inference::name),
        row.measured.dofs,
        row.measured.seconds,
        end_time / row.measured.seconds,
        opt(e.breakaway),
        opt(e.first_slip_duration),
        opt(e.period),
        opt(e.corridor),
        e.rms,
        row.on_front as u8
    )
}

/// A point of the measured front as the `auto` fidelity reads it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrontPoint {
    pub configuration: Configuration,
    /// Wall time measured in the study (s).
    pub seconds: f64,
    /// RMS tip-deflection error against the study's reference (m).
    pub rms_error: f64,
}

pub fn front_points(rows: &[Row]) -> Vec<FrontPoint> {
    front(rows)
        .into_iter()
        .map(|r| FrontPoint {
            configuration: r.measured.configuration,
            seconds: r.measured.seconds,
            rms_error: r.errors.rms,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(seconds: f64, rms: f64) -> Row {
        Row {
            measured: Measured {
                configuration: Configuration {
                    resolution: Resolution::Beam { elements: 1 },
                    dt: 1e-3,
                    scheme: Scheme::GeneralizedAlpha,
                    inference: None,
                },
                dofs: 2,
                seconds,
                summary: Summary::new(&[], &[]),
                tip: vec![],
            },
            errors: Errors {
                rms,
                ..Errors::default()
            },
            on_front: false,
        }
    }

    #[test]
    fn the_front_keeps_exactly_the_undominated_points() {
        // (time, error): (1, 9) (2, 5) (3, 6) dominated by (2, 5), (4, 1), (5, 1)
        // dominated by (4, 1), and a NaN error never on the front.
        let mut rows: Vec<Row> = [(1.0, 9.0), (2.0, 5.0), (3.0, 6.0), (4.0, 1.0), (5.0, 1.0)]
            .iter()
            .map(|&(t, e)| row(t, e))
            .chain([row(0.5, f64::NAN)])
            .collect();
        mark_pareto_front(&mut rows);
        let marks: Vec<bool> = rows.iter().map(|r| r.on_front).collect();
        assert_eq!(marks, [true, true, false, true, false, false]);
        let errors: Vec<f64> = front(&rows).iter().map(|r| r.errors.rms).collect();
        assert_eq!(errors, [9.0, 5.0, 1.0]);
    }

    #[test]
    fn the_full_grid_is_the_issues_grid_and_its_reference_is_the_finest_run() {
        let grid = Grid::full();
        assert_eq!(grid.configurations().len(), (6 + 6 + 5 + 5) * 7 * 2);
        let finest = grid.finest().unwrap();
        assert_eq!(
            finest.resolution,
            Resolution::PlaneStress {
                element_size: 0.005
            }
        );
        assert_eq!(finest.dt, 1e-5);
        // Every time step divides the comparison grid.
        for dt in grid.time_steps {
            let every = COMPARISON_INTERVAL / dt;
            assert!((every - every.round()).abs() < 1e-9, "{dt}");
        }
    }

    #[test]
    fn rms_difference_of_a_constant_offset_is_the_offset() {
        let a = [1.0, 2.0, 3.0];
        let b = [1.5, 2.5, 3.5];
        assert!((rms_difference(&a, &b) - 0.5).abs() < 1e-15);
    }
}
