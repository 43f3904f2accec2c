
/// `simulate --weights` takes the .onnx file: the run is the one of the JSON that
/// import-network writes from it, byte for byte.
#[test]
fn simulate_takes_an_onnx_file_as_weights() {
    let onnx = seed("seed-torch-f32-sigmoid-2-3-2-1.onnx");
    let json = scratch("simulate.json");
    let (ok, _, stderr) = import(&onnx, &json, &[]);
    assert!(ok, "{stderr}");
    let mut runs = Vec::new();
    for weights in [&onnx, &json] {
        let csv = scratch(&format!("simulate-{}.csv", runs.len()));
        let (ok, stdout, stderr) = stickslip(&[
            "simulate",
            "--friction",
            "neural",
            "--weights",
            weights.to_str().unwrap(),
            "--fidelity",
            "modal",
            "--t-end",
            "0.5",
            "--out",
            csv.to_str().unwrap(),
        ]);
        assert!(ok, "{stderr}");
        assert!(stdout.contains("breakaway time"), "{stdout}");
        runs.push(std::fs::read(&csv).unwrap());
        std::fs::remove_file(csv).unwrap();
    }
    assert!(runs[0] == runs[1], "the .onnx and its JSON ran differently");
    std::fs::remove_file(json).unwrap();
}
