//! Exported networks import as the network they came from: f64 exports bit for bit, f32
//! exports as the rounded network, the small network in every form.

use super::*;

/// f64 exports in the common forms map one to one onto the model (Sub/Div -> mean/std,
/// Gemm or MatMul + Add -> weights as stored, Mul/Add -> output std/mean), so the
/// imported model is the same numbers and every evaluation is bit-identical, for both
/// shipped models (plain and signed).
#[test]
fn f64_exports_import_bit_for_bit() {
    for signed in [false, true] {
        let model = paper(signed);
        for exporter in [Exporter::Torch, Exporter::Skl] {
            let what = format!("{exporter:?} f64, signed {signed}");
            let onnx = export(&model, exporter, false);
            let network = read_onnx(&onnx.encode(), "test.onnx").unwrap();
            assert_eq!(network.precision, Precision::F64, "{what}");
            let imported = import(&onnx).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_same_network(&imported, &model, &what);
            let (worst, identical) = compare(&imported, &model);
            assert!(identical, "{what}: differs by up to {worst:e} N");
        }
    }
}

/// f32 exports: FLOAT widens to f64 exactly, so the import is exactly the f32-rounded
/// network (bit-identical evaluations). Against the f64 original it differs by the
/// weights' rounding, relative 2^-24 = 6e-8 each, which moves the force by about 6e-8
/// times the output's condition (sum over paths of |weight products| times the
/// activations, relative to the force). Measured for the shipped 3 x 100 tanh networks:
/// 1e-6 to 2.2e-6 N on forces up to 55 N, i.e. 4e-8 relative (condition ~1); bounded by
/// 1e-6 of the largest force (a condition of 16 would still pass, a lost bit in the
/// import would not: that is 1e-7 relative per weight and adds up over 100 units).
#[test]
fn f32_exports_import_the_rounded_network() {
    for signed in [false, true] {
        let model = paper(signed);
        let largest = points(&model)
            .iter()
            .map(|p| {
                NeuralLaw::new(model.clone())
                    .unwrap()
                    .evaluate(p)
                    .unwrap()
                    .abs()
            })
            .fold(0.0, f64::max);
        for exporter in [Exporter::Torch, Exporter::Skl] {
            let what = format!("{exporter:?} f32, signed {signed}");
            let onnx = export(&model, exporter, true);
            let network = read_onnx(&onnx.encode(), "test.onnx").unwrap();
            assert_eq!(network.precision, Precision::F32, "{what}");
            let imported = import(&onnx).unwrap_or_else(|e| panic!("{what}: {e}"));
            let reference = rounded(&model, exporter == Exporter::Skl);
            assert_same_network(&imported, &reference, &what);
            let (_, identical) = compare(&imported, &reference);
            assert!(identical, "{what}");
            let (worst, _) = compare(&imported, &model);
            println!("{what}: largest deviation from f64 {worst:.3e} N of {largest:.1} N");
            assert!(worst <= 1e-6 * largest, "{what}: {worst:e} N");
            assert!(worst > 0.0, "{what}: f32 rounding must show");
        }
    }
}

#[test]
fn small_network_imports_in_every_form() {
    let model = small();
    for exporter in [Exporter::Torch, Exporter::Skl] {
        let imported = import(&export(&model, exporter, false)).unwrap();
        assert_same_network(&imported, &model, &format!("{exporter:?}"));
    }
}
