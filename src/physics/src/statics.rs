//! The paper's static load case (Sec. 2.1): the plane-stress tip deflection under a tip
//! load against Euler-Bernoulli (paper Eq. 2) and Timoshenko, over a sequence of element
//! sizes (the paper's Fig. 1b).

use crate::choice::Choice;
use crate::scene::{CheckedScene, Clamp};
use crate::structure::{
    euler_bernoulli_tip_deflection, plane_stress_nodes, timoshenko_tip_deflection, ModelError,
    StructuralModel,
};

/// One row of the mesh-convergence study.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ConvergenceRow {
    pub clamp: &'static str,
    pub element_size: f64,
    pub nodes: usize,
    pub dofs: usize,
    pub deflection: f64,
    /// Relative error against Euler-Bernoulli, (delta - delta_EB) / delta_EB.
    pub error_euler_bernoulli: f64,
    /// Relative error against Timoshenko (Euler-Bernoulli plus shear).
    pub error_timoshenko: f64,
}

/// Plane-stress static tip deflection over a sequence of element sizes, both clamps.
pub fn convergence_study(
    scene: &CheckedScene,
    load: f64,
    sizes: &[f64],
) -> Result<Vec<ConvergenceRow>, ModelError> {
    let eb = euler_bernoulli_tip_deflection(scene, load);
    let timo = timoshenko_tip_deflection(scene, load);
    let mut rows = Vec::new();
    for &clamp in Clamp::ALL {
        for &size in sizes {
            let model = StructuralModel::plane_stress_clamped(scene, size, clamp);
            let d = model.static_tip_deflection(load)?;
            rows.push(ConvergenceRow {
                clamp: clamp.name(),
                element_size: size,
                nodes: plane_stress_nodes(scene, size),
                dofs: model.dofs(),
                deflection: d,
                error_euler_bernoulli: (d - eb) / eb,
                error_timoshenko: (d - timo) / timo,
            });
        }
    }
    Ok(rows)
}
