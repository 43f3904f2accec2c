//! How a network is evaluated in the time loop: speed for accuracy (the scene's
//! `friction.inference`; the law it gives is built by `crate::law_source`).

crate::choice! {
    /// How the neural law is evaluated in the time loop (ignored by the other laws).
    #[choice(name = "Inference", description = "How the network of a neural law is evaluated")]
    #[derive(Default)]
    pub enum Inference {
        /// The network in f64, as trained.
        #[default]
        Exact = "exact": "the network in f64, as trained",
        /// The network in f32 (`neural::NeuralLaw::in_f32`).
        F32 = "f32": "the network in single precision (its largest deviation measured at build)",
        /// A table of the network over its training range, built at initialisation
        /// (`neural::table`).
        Table = "table": "a table of the network over its training range, built at initialisation (largest error verified at build)",
    }
}
