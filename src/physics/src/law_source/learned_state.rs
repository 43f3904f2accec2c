//! Where a scene names the learned law with memory: `friction.law = "neural"` with
//! `friction.weights` a file of format `stickslip-state-friction` (the memoryless
//! network's files have another format). Told by the file's `format` field, so no scene
//! field is added and every place that takes a weights file takes this one.

use std::path::Path;
use std::sync::Arc;

use crate::choice::Choice;
use crate::friction::learned_state::{LearnedStateLaw, StateLawFile};
use crate::friction::FrictionLawKind;
use crate::neural::inference::Inference;
use crate::neural::NeuralError;
use crate::neural::SceneLawError;
use crate::scene::{CheckedScene, Scene, SlidingVelocity};

/// The learned state law a scene names, if it names one; refused with the reason when
/// the file is corrupt or the scene asks for what a law with state cannot do (the same
/// rules as the analytical laws with state: relative sliding velocity, no modal slip
/// phase; and it is evaluated exactly, never as an f32 network or a table).
pub fn scene_state_law(
    scene: &CheckedScene,
) -> Result<Option<Arc<LearnedStateLaw>>, SceneLawError> {
    let friction = &scene.friction;
    let Some(path) = friction
        .weights
        .as_ref()
        .filter(|_| friction.law == FrictionLawKind::Neural)
    else {
        return Ok(None);
    };
    // A file that cannot be read is reported by the network reader, which reads it the
    // same way.
    let Ok(text) = crate::files::WEIGHTS_FILE.read_text(Path::new(path)) else {
        return Ok(None);
    };
    if !StateLawFile::is_state_law(&text) {
        return Ok(None);
    }
    let refuse = |source: NeuralError| SceneLawError::weights(path, source);
    let file = StateLawFile::from_json(&text, path).map_err(refuse)?;
    match refusal(scene) {
        Some(reason) => Err(refuse(NeuralError::NotAFrictionLaw(reason))),
        None => Ok(Some(Arc::new(file.law()))),
    }
}

/// Why `scene` cannot run a law with state, if it cannot: the rules of the analytical
/// laws with state (relative sliding velocity, no modal slip phase) and exact evaluation.
pub fn refusal(scene: &Scene) -> Option<String> {
    let friction = &scene.friction;
    if friction.inference != Inference::Exact {
        Some(format!(
            "friction.inference = {}: a law with state is evaluated exactly (inference = exact)",
            friction.inference.name()
        ))
    } else if scene.contact.sliding_velocity != SlidingVelocity::Relative {
        Some("a law with state needs contact.sliding_velocity = relative (its state evolves with the relative slip velocity)".into())
    } else if scene.contact.slip_modes_below > 0.0 {
        Some("a law with state needs contact.slip_modes_below = 0 (it has no stick phase to keep on the full mesh)".into())
    } else {
        None
    }
}

/// A fingerprint of the law's numbers for caches (`LawSource::fingerprint`).
pub fn fingerprint(law: &LearnedStateLaw) -> Option<String> {
    use std::hash::{Hash, Hasher};
    let text = serde_json::to_string(&(&law.parameters, &law.correction)).ok()?;
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    text.hash(&mut hasher);
    Some(format!("neural-memory {:016x}", hasher.finish()))
}
