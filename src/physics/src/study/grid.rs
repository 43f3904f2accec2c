//! The axes of a study: resolutions, time steps, integrators, friction laws and
//! inferences.

use super::configuration::{Configuration, Resolution};
use super::law::Law;
use crate::friction::FrictionLawKind;
use crate::neural::inference::Inference;
use crate::scene::Scheme;

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
    /// Evaluations of a neural law; empty: the scene's own. Laws other than `neural`
    /// have no inference, so the axis applies to the neural laws of [`Grid::laws`] only.
    pub inferences: Vec<Inference>,
    /// Friction laws (issue 24); empty: the scene's own. Each law's runs are compared
    /// with that law's reference ([`Grid::finest_for`]).
    pub laws: Vec<Law>,
}

impl Grid {
    /// The grid: modal 1..20 modes, beam 5..200 elements, plane stress
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
            laws: Vec::new(),
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

    /// The laws of the study: [`Grid::laws`], or the scene's own law (the law of every
    /// run before the axis existed).
    pub fn laws_or(&self, scene_law: Law) -> Vec<Law> {
        if self.laws.is_empty() {
            vec![scene_law]
        } else {
            self.laws.clone()
        }
    }

    /// The configurations run with `law`: [`Grid::configurations`], without the
    /// inference axis unless the law is a network (an analytical law would run the
    /// same numbers once per inference).
    pub fn configurations_for(&self, law: &Law) -> Vec<Configuration> {
        self.for_law(law).configurations()
    }

    /// `law`'s reference: [`Grid::finest`] of the grid `law` runs.
    pub fn finest_for(&self, law: &Law) -> Option<Configuration> {
        self.for_law(law).finest()
    }

    fn for_law(&self, law: &Law) -> Grid {
        let mut grid = self.clone();
        if law.kind() != FrictionLawKind::Neural {
            grid.inferences.clear();
        }
        grid
    }
}
