//! The arguments of the JS API, read at the boundary. wasm-bindgen's own conversions trap on a
//! number passed for a string, turn `null`, `[]` or `true` into numbers and wrap integers modulo
//! 2^32, so the API takes `JsValue`s and reads them here: a value of the wrong type, NaN,
//! Infinity, a fraction, or one out of range is an error naming the parameter.

use crate::util::shown;
use wasm_bindgen::prelude::*;

/// A value as an error message shows it (cut to 40 characters).
fn describe(v: &JsValue) -> String {
    if let Some(s) = v.as_string() {
        return format!("'{}' (a string)", shown(&s));
    }
    if let Some(n) = v.as_f64() {
        return n.to_string();
    }
    if v.is_null() {
        return "null".into();
    }
    if v.is_undefined() {
        return "undefined".into();
    }
    if let Some(b) = v.as_bool() {
        return format!("{b} (a boolean)");
    }
    format!("a value of type {}", shown(&v.js_typeof().as_string().unwrap_or_default()))
}

/// A string.
pub fn string(v: &JsValue, name: &str) -> Result<String, JsError> {
    v.as_string().ok_or_else(|| JsError::new(&format!("{name}: {} is not a string", describe(v))))
}

/// Bytes: a `Uint8Array` or an `ArrayBuffer`; `null`, `undefined` or anything else is refused
/// by name (wasm-bindgen's own conversion throws a TypeError naming nothing).
pub fn bytes(v: &JsValue, name: &str) -> Result<Vec<u8>, JsError> {
    if let Some(a) = v.dyn_ref::<js_sys::Uint8Array>() {
        return Ok(a.to_vec());
    }
    if let Some(b) = v.dyn_ref::<js_sys::ArrayBuffer>() {
        return Ok(js_sys::Uint8Array::new(b).to_vec());
    }
    Err(JsError::new(&format!("{name}: {} is not a Uint8Array", describe(v))))
}

/// A whole number in `lo..=hi` (an actual number: not a string, null or boolean).
pub fn whole(v: &JsValue, name: &str, lo: u64, hi: u64) -> Result<u64, JsError> {
    match v.as_f64() {
        Some(x) if x.is_finite() && x.fract() == 0.0 && x >= lo as f64 && x <= hi as f64 => Ok(x as u64),
        _ => Err(JsError::new(&format!("{name}: {} is out of range {lo}..={hi} (whole numbers)", describe(v)))),
    }
}

/// `whole`, or `None` for `undefined` or `null` (an optional argument left out).
pub fn optional_whole(v: &JsValue, name: &str, lo: u64, hi: u64) -> Result<Option<u64>, JsError> {
    if v.is_undefined() || v.is_null() {
        return Ok(None);
    }
    whole(v, name, lo, hi).map(Some)
}

/// An optional argument (`Option<JsValue>`: left out, `undefined` or `null` is `None`) read as
/// `whole`.
pub fn optional(v: Option<JsValue>, name: &str, lo: u64, hi: u64) -> Result<Option<u64>, JsError> {
    v.map_or(Ok(None), |v| optional_whole(&v, name, lo, hi))
}

/// A JS value as JSON text, read in full before anything of the run is touched: `JSON.stringify`
/// catches a getter that throws (or calls back into the run), which would otherwise unwind
/// through the wasm and leave the run borrowed for good; NaN and Infinity, which JSON would turn
/// into null (and so into a default), come out as strings the parser refuses by name.
pub fn json(v: &JsValue, name: &str) -> Result<String, JsError> {
    let replacer =
        Closure::<dyn Fn(JsValue, JsValue) -> JsValue>::new(|_key: JsValue, value: JsValue| match value.as_f64() {
            Some(x) if !x.is_finite() => JsValue::from_str(&format!("{x} (not a finite number)")),
            _ => value,
        });
    let text = js_sys::JSON::stringify_with_replacer(v, replacer.as_ref().unchecked_ref())
        .map_err(|e| JsError::new(&format!("{name}: could not be read ({})", describe_error(&e))))?;
    text.as_string().ok_or_else(|| JsError::new(&format!("{name}: {} is not an object", describe(v))))
}

fn describe_error(e: &JsValue) -> String {
    let message = js_sys::Reflect::get(e, &JsValue::from_str("message")).ok().and_then(|m| m.as_string());
    shown(&message.unwrap_or_else(|| describe(e)))
}
