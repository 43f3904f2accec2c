//! The network weights an FMU reads from its `resources/` folder, read once per name
//! and shared from then on (`Arc`): StickSlipBeam hands the loaded network to its law
//! source (`stickslip::law_source::LawSource`), and `fidelity = auto`'s calibration
//! runs use that one, never reading the file again.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use stickslip::files::WEIGHTS_FILE;
use stickslip::friction::learned_state::{LearnedStateLaw, StateLawFile};
use stickslip::neural::{NeuralError, NeuralLaw};

/// The weights read at instantiation (the paper's network, see `neural`).
pub const DEFAULT_WEIGHTS: &str = "paper-plain.json";

/// Network weights shipped in `resources/`, shared by both FMUs: the files of the same
/// name in the workspace's `weights/` folder.
/// `rate-and-state-learned.json` is the learned law with memory (`friction::learned_state`).
pub const WEIGHTS_RESOURCES: &[&str] = &[
    "paper-plain.json",
    "paper-signed.json",
    "rate-and-state-learned.json",
];

/// A weights parameter's value: any non-blank name (whether the file exists is checked
/// when it is read).
pub fn weights_name(value: &str) -> Result<String, String> {
    if value.trim().is_empty() {
        Err("must name a weights file".into())
    } else {
        Ok(value.to_owned())
    }
}

/// Why a network could not be had. Each message names the file once: the reader's
/// errors name it (`stickslip::files`, `NeuralLaw::from_file`), so none is added here.
#[derive(Debug, thiserror::Error)]
pub enum NetworkError {
    /// A relative name before any resources folder was given.
    #[error("weights \"{name}\": no resources folder is known")]
    NoFolder { name: String },
    /// The file is not there, not a regular file, unreadable, or not a network.
    #[error(transparent)]
    Unreadable(#[from] NeuralError),
}

/// Networks read so far, by the name they were asked for.
#[derive(Default)]
pub struct Networks {
    folder: Option<PathBuf>,
    loaded: Vec<(String, Arc<NeuralLaw>)>,
    /// Weights names looked at for a learned law with state: the law, or `None` for a
    /// file of another format (a memoryless network).
    state_laws: Vec<(String, Option<Arc<LearnedStateLaw>>)>,
}

impl Networks {
    /// Remembers the unpacked `resources/` folder and checks that the default weights
    /// file is there, so that a missing resources folder fails instantiation. Nothing is
    /// parsed: a model whose law needs no network never pays for one.
    pub fn open(&mut self, folder: &Path) -> Result<(), NetworkError> {
        self.folder = Some(folder.to_path_buf());
        WEIGHTS_FILE
            .check(&folder.join(DEFAULT_WEIGHTS))
            .map_err(|e| NetworkError::Unreadable(e.into()))
    }

    /// [`Self::open`], then reads the default weights, so that a corrupted file fails
    /// instantiation: for an FMU whose default law is the network.
    pub fn open_and_read_default(&mut self, folder: &Path) -> Result<(), NetworkError> {
        self.open(folder)?;
        self.get(DEFAULT_WEIGHTS).map(|_| ())
    }

    /// How many networks have been read (parsed) so far.
    pub fn read_count(&self) -> usize {
        self.loaded.len()
    }

    /// Weights `name`: a file in `resources/`, or an absolute path. Clone the `Arc` to
    /// share the network; `Arc::make_mut` evaluates it in place while it is not shared
    /// (NeuralFriction's evaluations keep scratch buffers in the network).
    pub fn get(&mut self, name: &str) -> Result<&mut Arc<NeuralLaw>, NetworkError> {
        let k = match self.loaded.iter().position(|(n, _)| n == name) {
            Some(k) => k,
            None => {
                let law = self.read(name)?;
                self.loaded.push((name.to_owned(), Arc::new(law)));
                self.loaded.len() - 1
            }
        };
        Ok(&mut self.loaded[k].1)
    }

    /// The learned law with state that weights `name` hold, or `None` when the file is
    /// of another format (told by its `format` field; `get` then reads it as a network).
    /// A corrupt state-law file is refused with the reason.
    pub fn state_law(&mut self, name: &str) -> Result<Option<Arc<LearnedStateLaw>>, NetworkError> {
        if let Some((_, law)) = self.state_laws.iter().find(|(n, _)| n == name) {
            return Ok(law.clone());
        }
        let full = self.path_of(name)?;
        let law = match WEIGHTS_FILE.read_text(&full) {
            Ok(text) if StateLawFile::is_state_law(&text) => {
                let file = StateLawFile::from_json(&text, &full.display().to_string())
                    .map_err(|e| e.in_file(&full))?;
                Some(Arc::new(file.law()))
            }
            // Unreadable or another format: the network reader, which reads it the same
            // way, reports it.
            _ => None,
        };
        self.state_laws.push((name.to_owned(), law.clone()));
        Ok(law)
    }

    /// The file that weights `name` are read from: in `resources/`, or the absolute path
    /// itself (whether it is a readable file is the reader's to say).
    fn path_of(&self, name: &str) -> Result<PathBuf, NetworkError> {
        let path = Path::new(name);
        let full = if path.is_absolute() {
            path.to_path_buf()
        } else {
            match &self.folder {
                Some(dir) => dir.join(path),
                None => {
                    return Err(NetworkError::NoFolder {
                        name: name.to_owned(),
                    })
                }
            }
        };
        Ok(full)
    }

    fn read(&self, name: &str) -> Result<NeuralLaw, NetworkError> {
        Ok(NeuralLaw::from_file(&self.path_of(name)?)?)
    }
}
