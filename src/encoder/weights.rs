//! The autoencoder weights file: small, versioned and checked, so a corrupt or mismatched file is
//! a clear error instead of a wrong embedding.
//!
//! Layout, little-endian:
//! - magic `SECAEWTS` (8 bytes), format version (u32, now 1), value type (u32: 1 = f32, 2 = f16,
//!   3 = f16 in two byte planes);
//! - the task name (u16 length + UTF-8) and the per-model embedding scale (f32);
//! - the tensor count (u32), then per tensor its name (u16 length + UTF-8), rank (u8) and dims (u32
//!   each);
//! - every tensor's values in order (f32 or IEEE half); with byte planes, the low bytes of all the
//!   halves, then their high bytes: the same values, but the high bytes (sign, exponent) repeat and
//!   gzip finds them, so the page downloads 24 KB less per model;
//! - an FNV-1a 64 checksum (u64) of all the bytes before it.

use crate::error::{ConfigError, FileError};
use crate::util::{fnv1a, put_str, ByteReader};

/// A weights file's first bytes.
pub const MAGIC: [u8; 8] = *b"SECAEWTS";
/// The format version this build reads and writes.
pub const VERSION: u32 = 1;

/// How values are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DType {
    /// 32-bit floats.
    F32 = 1,
    /// 16-bit floats.
    F16 = 2,
    /// 16-bit floats stored as two byte planes (all low bytes, then all high bytes).
    F16Planes = 3,
}

/// The largest magnitude a weight may have (trained ones stay below 10).
pub const MAX_WEIGHT: f32 = 1e4;

/// One named tensor (row-major, shape as stored).
#[derive(Clone, Debug, PartialEq)]
pub struct Tensor {
    /// Its name in the model.
    pub name: String,
    /// Its shape.
    pub shape: Vec<usize>,
    /// Its values, row-major.
    pub data: Vec<f32>,
}

/// A weights file's content.
#[derive(Clone, Debug, PartialEq)]
pub struct Weights {
    /// The task the model was trained on.
    pub task: String,
    /// Multiplies the embedding; 1.0 is the authors' raw ReLU output (docs/ALGORITHM.md, D17).
    pub embedding_scale: f32,
    /// The model's tensors.
    pub tensors: Vec<Tensor>,
}

fn err(message: impl Into<String>) -> FileError {
    FileError::new("weights", message)
}

impl Weights {
    /// Serialises; f16 storage halves the size.
    pub fn to_bytes(&self, dtype: DType) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(&MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&(dtype as u32).to_le_bytes());
        put_str(&mut b, &self.task);
        b.extend_from_slice(&self.embedding_scale.to_le_bytes());
        b.extend_from_slice(&(self.tensors.len() as u32).to_le_bytes());
        for t in &self.tensors {
            put_str(&mut b, &t.name);
            b.push(t.shape.len() as u8);
            for &d in &t.shape {
                b.extend_from_slice(&(d as u32).to_le_bytes());
            }
        }
        let values = self.tensors.iter().flat_map(|t| t.data.iter().copied());
        match dtype {
            DType::F32 => values.for_each(|v| b.extend_from_slice(&v.to_le_bytes())),
            DType::F16 => values.for_each(|v| b.extend_from_slice(&half::f16::from_f32(v).to_le_bytes())),
            DType::F16Planes => {
                let halves: Vec<[u8; 2]> = values.map(|v| half::f16::from_f32(v).to_le_bytes()).collect();
                b.extend(halves.iter().map(|h| h[0]));
                b.extend(halves.iter().map(|h| h[1]));
            }
        }
        let sum = fnv1a(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// Parses and checks a file: magic, version, checksum, sizes.
    pub fn from_bytes(bytes: &[u8]) -> Result<Weights, FileError> {
        if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
            return Err(err("not a SEC autoencoder weights file (bad magic number)"));
        }
        if bytes.len() < MAGIC.len() + 8 + 8 {
            return Err(err("file is truncated"));
        }
        let (body, tail) = bytes.split_at(bytes.len() - 8);
        let stored = u64::from_le_bytes(tail.try_into().unwrap());
        let mut r = ByteReader { b: body, at: MAGIC.len(), what: "weights" };
        let version = r.u32()?;
        if version != VERSION {
            return Err(err(format!("format version {version} is not supported (this build reads {VERSION})")));
        }
        if fnv1a(body) != stored {
            return Err(err("checksum mismatch: the file is corrupt"));
        }
        let dtype = match r.u32()? {
            1 => DType::F32,
            2 => DType::F16,
            3 => DType::F16Planes,
            d => return Err(err(format!("unknown value type {d} (1 = f32, 2 = f16, 3 = f16 byte planes)"))),
        };
        let task = r.string()?;
        let embedding_scale = f32::from_le_bytes(r.take(4)?.try_into().unwrap());
        check_scale(embedding_scale).map_err(|e| FileError::value("weights", e))?;
        let n = r.u32()? as usize;
        let mut heads = Vec::new();
        for _ in 0..n.min(1024) {
            let name = r.string()?;
            let rank = r.take(1)?[0] as usize;
            let shape = (0..rank).map(|_| r.u32().map(|d| d as usize)).collect::<Result<Vec<_>, _>>()?;
            heads.push((name, shape));
        }
        let mut counts = Vec::with_capacity(heads.len());
        for (_, shape) in &heads {
            counts.push(
                shape.iter().try_fold(1usize, |a, &d| a.checked_mul(d)).ok_or_else(|| err("tensor size overflows"))?,
            );
        }
        let total =
            counts.iter().try_fold(0usize, |a, &c| a.checked_add(c)).ok_or_else(|| err("tensor size overflows"))?;
        let width = if dtype == DType::F32 { 4 } else { 2 };
        let raw = r.take(total.checked_mul(width).ok_or_else(|| err("tensor size overflows"))?)?;
        let values: Vec<f32> = match dtype {
            DType::F32 => raw.chunks_exact(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect(),
            DType::F16 => raw.chunks_exact(2).map(|c| half::f16::from_le_bytes([c[0], c[1]]).to_f32()).collect(),
            DType::F16Planes => {
                let (low, high) = raw.split_at(total);
                low.iter().zip(high).map(|(&l, &h)| half::f16::from_le_bytes([l, h]).to_f32()).collect()
            }
        };
        let mut tensors = Vec::new();
        let mut rest = values.as_slice();
        for ((name, shape), count) in heads.into_iter().zip(counts) {
            let (data, after) = rest.split_at(count);
            rest = after;
            // Weights bound every activation: one infinite bias makes every embedding infinite.
            if let Some(v) = data.iter().find(|v: &&f32| !v.is_finite() || v.abs() > MAX_WEIGHT) {
                return Err(FileError::field(
                    "weights",
                    crate::util::shown(&name),
                    format!("holds {v}, outside the finite range +-{MAX_WEIGHT}"),
                ));
            }
            tensors.push(Tensor { name, shape, data: data.to_vec() });
        }
        if r.at != body.len() {
            return Err(err(format!("{} unexpected bytes after the tensors", body.len() - r.at)));
        }
        Ok(Weights { task, embedding_scale, tensors })
    }

    /// The tensor called `name` with exactly `shape`.
    pub fn tensor(&self, name: &str, shape: &[usize]) -> Result<&[f32], FileError> {
        let t = self.tensors.iter().find(|t| t.name == name).ok_or_else(|| err(format!("tensor {name} is missing")))?;
        if t.shape != shape {
            return Err(err(format!("tensor {name} has shape {:?}, expected {shape:?}", t.shape)));
        }
        Ok(&t.data)
    }
}

/// Allowed embedding scales: positive, and small enough that 20 scaled ReLU outputs stay finite.
pub const SCALE_RANGE: (f32, f32) = (0.0, 1.0e6);

/// Checks an `embeddingScale`: finite, in (0, 1e6].
pub fn check_scale(scale: f32) -> Result<(), ConfigError> {
    if scale.is_finite() && scale > SCALE_RANGE.0 && scale <= SCALE_RANGE.1 {
        Ok(())
    } else {
        Err(ConfigError::new(
            "embeddingScale",
            format!("{scale} is out of range ({}, {}]", SCALE_RANGE.0, SCALE_RANGE.1),
        ))
    }
}
