//! Small helpers shared by several modules.

use crate::error::FileError;

/// The largest text file (an Animal-AI YAML arena, a RunConfig) any front end reads: checked
/// while reading, so `/dev/zero` or a 10 GB file is refused at once, and again by the parsers.
pub const MAX_TEXT_FILE_BYTES: usize = 1 << 20;

/// `text` fits `MAX_TEXT_FILE_BYTES`, or an error naming `what`.
pub fn check_text_size(text: &str, what: &str) -> Result<(), String> {
    if text.len() > MAX_TEXT_FILE_BYTES {
        return Err(format!(
            "{what}: {} bytes is larger than {MAX_TEXT_FILE_BYTES}, the most a text file may be",
            text.len()
        ));
    }
    Ok(())
}

/// A user's file opened for reading if it is a regular file: a named pipe, a device, a socket or
/// a directory is refused by kind, naming `what` (the parameter or option the path came from),
/// before any read. On Unix the file is opened without blocking (a pipe with no writer would
/// block `open` itself), then its kind is read from the open handle, so a path swapped between
/// the check and the open cannot slip through.
#[cfg(not(target_arch = "wasm32"))]
pub fn open_regular_file(path: &std::path::Path, what: &str) -> Result<std::fs::File, String> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| format!("{what}: {}: {e}", path.display()))?;
    let kind = file.metadata().map_err(|e| format!("{what}: {}: {e}", path.display()))?.file_type();
    if !kind.is_file() {
        return Err(format!("{what}: {} is {}, not a regular file", path.display(), kind_name(kind)));
    }
    Ok(file)
}

/// What a file that is not a regular one is, for a refusal.
#[cfg(not(target_arch = "wasm32"))]
fn kind_name(kind: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a named pipe";
        }
        if kind.is_socket() {
            return "a socket";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
    }
    if kind.is_dir() {
        "a directory"
    } else {
        "not a file"
    }
}

/// A user's file (`open_regular_file`) read whole with the size limit `max` enforced while
/// reading, each refusal naming `what`.
#[cfg(not(target_arch = "wasm32"))]
pub fn read_regular_file(path: &std::path::Path, what: &str, max: usize) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let file = open_regular_file(path, what)?;
    let mut bytes = Vec::new();
    file.take(max as u64 + 1).read_to_end(&mut bytes).map_err(|e| format!("{what}: {}: {e}", path.display()))?;
    if bytes.len() > max {
        return Err(format!("{what}: {} is larger than {max} bytes, the most it may be", path.display()));
    }
    Ok(bytes)
}

/// A user's text file (`read_regular_file`, at most `MAX_TEXT_FILE_BYTES`), UTF-8 checked.
#[cfg(not(target_arch = "wasm32"))]
pub fn read_text_file(path: &std::path::Path, what: &str) -> Result<String, String> {
    let bytes = read_regular_file(path, what, MAX_TEXT_FILE_BYTES)?;
    String::from_utf8(bytes).map_err(|e| {
        format!("{what}: {} is not UTF-8 text (byte {}): not a text file", path.display(), e.utf8_error().valid_up_to())
    })
}

/// FNV-1a 64's starting value.
pub(crate) const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
/// FNV-1a 64's multiplier.
pub(crate) const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// 64-bit FNV-1a: frame fingerprints in traces and the weights file's checksum.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    fnv1a_extend(FNV_OFFSET, bytes)
}

/// FNV-1a 64 of what `h` hashed followed by `bytes` (a checksum computed as a file streams).
pub(crate) fn fnv1a_extend(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(FNV_PRIME);
    }
    h
}

/// A value as an error message shows it: cut after 40 characters, so that a pasted page of text
/// (or a 10 MiB name in a file) does not fill the screen.
pub fn shown(value: &str) -> String {
    const MAX: usize = 40;
    match value.char_indices().nth(MAX) {
        Some((at, _)) => format!("{}… ({} characters)", &value[..at], value.chars().count()),
        None => value.to_string(),
    }
}

/// Reads a little-endian binary file front to back; running past its end is a "truncated"
/// error naming `what` (the kind of file: "weights", "memory").
pub(crate) struct ByteReader<'a> {
    pub b: &'a [u8],
    pub at: usize,
    pub what: &'static str,
}

impl<'a> ByteReader<'a> {
    pub fn take(&mut self, n: usize) -> Result<&'a [u8], FileError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        let end = end.ok_or_else(|| FileError::new(self.what, "file is truncated"))?;
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    pub fn u32(&mut self) -> Result<u32, FileError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    pub fn u64(&mut self) -> Result<u64, FileError> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    pub fn f32(&mut self) -> Result<f32, FileError> {
        Ok(f32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    pub fn f64(&mut self) -> Result<f64, FileError> {
        Ok(f64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
    /// A u16 length and that many bytes of UTF-8.
    pub fn string(&mut self) -> Result<String, FileError> {
        let n = u16::from_le_bytes(self.take(2)?.try_into().unwrap()) as usize;
        let what = self.what;
        String::from_utf8(self.take(n)?.to_vec()).map_err(|_| FileError::new(what, "a name is not UTF-8"))
    }
}

impl ByteReader<'_> {
    /// A u64 count, refused past `max`.
    pub fn count(&mut self, max: usize, field: &str) -> Result<usize, FileError> {
        let n = self.u64()?;
        if n > max as u64 {
            return Err(FileError::field(self.what, field.to_string(), format!("{n} entries, more than {max}")));
        }
        Ok(n as usize)
    }
    /// A u64 count (at most `max`) and that many f32s, as `put_f32s` writes them.
    pub fn f32s(&mut self, max: usize, field: &str) -> Result<Vec<f32>, FileError> {
        let n = self.count(max, field)?;
        (0..n).map(|_| self.f32()).collect()
    }
    pub fn f64s(&mut self, max: usize, field: &str) -> Result<Vec<f64>, FileError> {
        let n = self.count(max, field)?;
        (0..n).map(|_| self.f64()).collect()
    }
    pub fn bytes(&mut self, max: usize, field: &str) -> Result<Vec<u8>, FileError> {
        let n = self.count(max, field)?;
        Ok(self.take(n)?.to_vec())
    }
    pub fn bool(&mut self) -> Result<bool, FileError> {
        match self.take(1)?[0] {
            0 => Ok(false),
            1 => Ok(true),
            b => Err(FileError::new(self.what, format!("{b} is not a boolean"))),
        }
    }
}

pub(crate) fn put_f32s(b: &mut Vec<u8>, v: &[f32]) {
    b.extend_from_slice(&(v.len() as u64).to_le_bytes());
    v.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
}

pub(crate) fn put_f64s(b: &mut Vec<u8>, v: &[f64]) {
    b.extend_from_slice(&(v.len() as u64).to_le_bytes());
    v.iter().for_each(|x| b.extend_from_slice(&x.to_le_bytes()));
}

pub(crate) fn put_bytes(b: &mut Vec<u8>, v: &[u8]) {
    b.extend_from_slice(&(v.len() as u64).to_le_bytes());
    b.extend_from_slice(v);
}

/// Writes `s` as `ByteReader::string` reads it.
pub(crate) fn put_str(b: &mut Vec<u8>, s: &str) {
    b.extend_from_slice(&(s.len() as u16).to_le_bytes());
    b.extend_from_slice(s.as_bytes());
}
