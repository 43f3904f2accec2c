//! The whole study: every law of the grid gets its reference run, then every
//! configuration is run with every law and compared with that law's reference.
//!
//! Why one reference per law: the laws differ by far more than the discretisation (over
//! the first 0.45 s of the paper scene, modal 3 modes, the exponential law and LuGre
//! differ by 12.5 um RMS, while halving the step moves either by 0.05 um at most; see
//! the unit test), so an error across laws would measure the law, not the
//! configuration.

use super::configuration::Configuration;
use super::errors::Errors;
use super::front::{mark_pareto_front, Row};
use super::grid::Grid;
use super::law::{Law, LawError};
use super::measure::{measure, Failed, Measured};
use crate::law_source::LawSource;
use crate::neural::SceneLawError;
use crate::scene::{Scene, SceneError};

/// A law's reference run.
#[derive(Clone, Debug)]
pub struct Reference {
    pub law: Law,
    pub measured: Measured,
}

/// Every run of a study: the references (one per law, in the grid's law order), the
/// rows (references left out: each is exact by definition, so its law's front ends at
/// the best run that can be compared with something better), and the runs that failed.
#[derive(Debug)]
pub struct Study {
    pub references: Vec<Reference>,
    pub rows: Vec<Row>,
    pub failures: Vec<(Law, Failed)>,
}

impl Study {
    /// The reference of `law`.
    pub fn reference(&self, law: &Law) -> Option<&Reference> {
        self.references.iter().find(|r| r.law == *law)
    }
}

/// Why a study could not run at all (a single configuration's failure is a row of
/// [`Study::failures`] instead).
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error("the grid is empty: give at least one resolution and one time step")]
    EmptyGrid,
    #[error(transparent)]
    Law(#[from] LawError),
    #[error("friction law {law}: {source}")]
    Scene { law: Law, source: SceneError },
    #[error("friction law {law}: {source}")]
    Source { law: Law, source: SceneLawError },
    /// A law's reference run failed; `law` is None for a study without a law axis (its
    /// message then stays the one the command line has always printed).
    #[error("{}the reference {} failed: {}", of_law(.law), .failed.configuration, .failed.reason)]
    Reference {
        law: Option<Law>,
        failed: Box<Failed>,
    },
}

fn of_law(law: &Option<Law>) -> String {
    law.as_ref()
        .map_or_else(String::new, |law| format!("friction law {law}: "))
}

/// What the study reports while it runs (the command line prints it).
#[derive(Debug)]
pub enum Progress<'a> {
    /// A law's reference has run.
    Reference(&'a Reference),
    /// Run `index` of `total` (all laws) gave `row`.
    Row {
        index: usize,
        total: usize,
        row: &'a Row,
    },
    /// Run `index` of `total` failed.
    Failed {
        index: usize,
        total: usize,
        law: &'a Law,
        failed: &'a Failed,
    },
}

/// Runs the study of `grid` on `scene`: per law (the grid's, or the scene's own), its
/// reference ([`Grid::finest_for`]) and then every configuration, one after the other so
/// that no two runs compete for a core, and marks each law's Pareto front.
pub fn run(
    scene: &Scene,
    grid: &Grid,
    mut progress: impl FnMut(Progress<'_>),
) -> Result<Study, StudyError> {
    let plan = plan(scene, grid)?;
    let mut references: Vec<Reference> = Vec::new();
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    let total = plan.len();
    for (
        index,
        Planned {
            law,
            configuration,
            reference: reference_configuration,
            source,
        },
    ) in plan.into_iter().enumerate()
    {
        let law_scene = law.apply(scene);
        if !references.iter().any(|r| r.law == law) {
            let measured =
                measure(&law_scene, &source, reference_configuration).map_err(|failed| {
                    StudyError::Reference {
                        law: (!grid.laws.is_empty()).then(|| law.clone()),
                        failed: Box::new(failed),
                    }
                })?;
            references.push(Reference {
                law: law.clone(),
                measured,
            });
            progress(Progress::Reference(references.last().expect("just pushed")));
        }
        if configuration == reference_configuration {
            continue;
        }
        let reference = &references
            .iter()
            .find(|r| r.law == law)
            .expect("the law's reference ran first")
            .measured;
        match measure(&law_scene, &source, configuration) {
            Ok(measured) => {
                let errors = Errors::between(&measured, reference);
                rows.push(Row {
                    law,
                    measured,
                    errors,
                    on_front: false,
                });
                progress(Progress::Row {
                    index: index + 1,
                    total,
                    row: rows.last().expect("just pushed"),
                });
            }
            Err(failed) => {
                progress(Progress::Failed {
                    index: index + 1,
                    total,
                    law: &law,
                    failed: &failed,
                });
                failures.push((law, failed));
            }
        }
    }
    mark_pareto_front(&mut rows);
    Ok(Study {
        references,
        rows,
        failures,
    })
}

/// One run of the study as planned: a law, the configuration to run, the law's
/// reference configuration and the law's source, resolved once per law.
struct Planned {
    law: Law,
    configuration: Configuration,
    reference: Configuration,
    source: LawSource,
}

/// Every run of the study, law by law (the grid's, or the scene's own), each law's
/// configurations in the grid's order.
fn plan(scene: &Scene, grid: &Grid) -> Result<Vec<Planned>, StudyError> {
    let laws = grid.laws_or(Law::of_scene(scene)?);
    let mut plan = Vec::new();
    for law in &laws {
        let reference = grid.finest_for(law).ok_or(StudyError::EmptyGrid)?;
        let scene = law.apply(scene);
        // The law's source is resolved once (a weights file read once) on the scene
        // as its reference runs it: any configuration would do, but the scene's own
        // level may be `auto`, which a law with state refuses.
        let checked = reference
            .apply(&scene)
            .check()
            .map_err(|source| StudyError::Scene {
                law: law.clone(),
                source,
            })?;
        let source = LawSource::resolve(&checked).map_err(|source| StudyError::Source {
            law: law.clone(),
            source,
        })?;
        for configuration in grid.configurations_for(law) {
            plan.push(Planned {
                law: law.clone(),
                configuration,
                reference,
                source: source.clone(),
            });
        }
    }
    Ok(plan)
}
