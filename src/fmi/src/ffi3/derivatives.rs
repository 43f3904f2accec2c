//! fmi3GetDirectionalDerivative: the buffers become slices, `values3` expands arrays,
//! and the instance computes (`Instance::get_directional_derivative`). StickSlipBeam
//! answers fmi3Error (its providesDirectionalDerivatives is false).

use super::types::*;
use super::values3;
use crate::boundary::{each, null_argument, slice, slice_mut, status, with_component};
use libc::size_t;

#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: size_t,
    knowns: *const fmi3ValueReference,
    nKnowns: size_t,
    seed: *const fmi3Float64,
    nSeed: size_t,
    sensitivity: *mut fmi3Float64,
    nSensitivity: size_t,
) -> fmi3Status {
    const CALL: &str = "fmi3GetDirectionalDerivative";
    unsafe {
        with_component(instance, CALL, |component| {
            let (Some(unknowns), Some(knowns), Some(seed), Some(out)) = (
                slice(unknowns, nUnknowns),
                slice(knowns, nKnowns),
                slice(seed, nSeed),
                slice_mut(sensitivity, nSensitivity),
            ) else {
                return null_argument(component, CALL, "unknowns, knowns, seed or sensitivity");
            };
            status(each!(&mut component.instance, i => {
                values3::directional_derivative(i, unknowns, knowns, seed, out)
            }))
        })
    }
}
