//! fmi3GetDirectionalDerivative: the buffers become slices, `values3` expands arrays,
//! and the instance computes (`Instance::get_directional_derivative`). StickSlipBeam
//! answers fmi3Error (its providesDirectionalDerivatives is false).

use super::types::*;
use super::values3;
use crate::boundary::{
    component_at, each, null_argument, slice, slice_mut, status, with_component,
};
use libc::size_t;

/// # Safety
///
/// `instance` is NULL or a live instance of fmi3InstantiateCoSimulation that no other
/// call uses meanwhile; `unknowns`, `knowns`, `seed` and `sensitivity` are each NULL or
/// as many elements as the length beside them (`sensitivity` writable and used by
/// nothing else).
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
    // SAFETY: the importer's obligation on `instance` above.
    let component = unsafe { component_at(instance) };
    with_component(component, CALL, |component| {
        // SAFETY: NULL with a non-zero length is refused below; otherwise the lengths
        // given, by the importer's obligation.
        let arrays = unsafe {
            (
                slice(unknowns, nUnknowns),
                slice(knowns, nKnowns),
                slice(seed, nSeed),
                slice_mut(sensitivity, nSensitivity),
            )
        };
        let (Some(unknowns), Some(knowns), Some(seed), Some(out)) = arrays else {
            return null_argument(component, CALL, "unknowns, knowns, seed or sensitivity");
        };
        status(each!(&mut component.instance, i => {
            values3::directional_derivative(i, unknowns, knowns, seed, out)
        }))
    })
}
