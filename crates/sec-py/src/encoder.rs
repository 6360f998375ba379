//! `Encoder`: a task's bundled autoencoder (embed, reconstruct, the gate's error) and frames'
//! fingerprints.

use crate::checks::{check_seed, value_error, SIDE};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray3};
use pyo3::prelude::*;
use sec_playground::encoder::{Perception, PerceptionKind, Scratch, EMBEDDING};

/// A bundled encoder: the task's trained autoencoder, or the untrained one the authors' agent
/// embedded with (D20), drawn from `seed`.
#[pyclass(module = "sec_playground._core", name = "Encoder")]
pub(crate) struct PyEncoder {
    perception: Perception,
    scratch: Scratch,
}

#[pymethods]
impl PyEncoder {
    #[new]
    #[pyo3(signature = (task, perception="trained", seed=0))]
    fn new(task: &str, perception: &str, seed: u64) -> PyResult<Self> {
        check_seed(seed)?;
        let kind: PerceptionKind = serde_json::from_value(serde_json::Value::String(perception.into()))
            .map_err(|_| value_error(format!("perception: '{perception}' is not 'trained' or 'untrained'")))?;
        let perception = Perception::new(kind, task, None, seed).map_err(value_error)?;
        Ok(PyEncoder { perception, scratch: Scratch::default() })
    }

    /// The embedding of one camera frame (84x84x3 bytes): 20 floats.
    fn encode<'py>(&mut self, py: Python<'py>, frame: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArray1<f32>>> {
        let frame = frame_of(frame)?;
        let bytes = frame.as_array();
        let image: Vec<f32> = bytes.iter().map(|&b| b as f32 / 255.0).collect();
        let mut e = [0.0f32; EMBEDDING];
        self.perception.embed(&image, &mut self.scratch, &mut e);
        Ok(e.to_vec().into_pyarray(py))
    }
}

/// A camera frame: a uint8 array of shape (84, 84, 3); anything else is refused naming what it
/// is (its dtype and shape, or its type), not with numpy's "type mismatch".
pub(crate) fn frame_of<'py>(obj: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArray3<'py, u8>> {
    let what = || match (obj.getattr("dtype"), obj.getattr("shape")) {
        (Ok(dtype), Ok(shape)) => format!("an array of {dtype} and shape {shape}"),
        _ => format!("a {}", obj.get_type().name().map(|n| n.to_string()).unwrap_or_default()),
    };
    let frame = obj
        .extract::<PyReadonlyArray3<'py, u8>>()
        .map_err(|_| value_error(format!("frame: {} is not a uint8 array of shape (84, 84, 3)", what())))?;
    if frame.as_array().shape() != [SIDE, SIDE, 3] {
        return Err(value_error(format!("frame: {} is not a uint8 array of shape (84, 84, 3)", what())));
    }
    Ok(frame)
}

/// The fingerprint the golden traces hold of a frame: FNV-1a over its RGBA bytes (alpha 255).
#[pyfunction]
pub(crate) fn fingerprint(frame: &Bound<'_, PyAny>) -> PyResult<u64> {
    let frame = frame_of(frame)?;
    let bytes = frame.as_array();
    let rgb: Vec<u8> = bytes.iter().copied().collect();
    let rgba: Vec<u8> = rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    Ok(sec_playground::render::fnv1a(&rgba))
}
