//! Reading typed properties of glTF JSON objects, and the errors for the ones that break the
//! rules; shared by every check.

use crate::error::{GlbErrorKind, Result, glb_error};
use serde_json::Value;

pub(super) fn property(
    element: &'static str,
    index: usize,
    property: &'static str,
) -> crate::Error {
    glb_error(GlbErrorKind::Property {
        element,
        index,
        property,
    })
}

pub(super) fn rule(element: &'static str, index: usize, rule: &'static str) -> crate::Error {
    glb_error(GlbErrorKind::Rule {
        element,
        index,
        rule,
    })
}

pub(super) fn list<'a>(root: &'a Value, key: &'static str) -> Result<&'a [Value]> {
    match root.get(key) {
        None => Ok(&[]),
        Some(Value::Array(a)) => Ok(a),
        Some(_) => Err(property("root", 0, key)),
    }
}

pub(super) fn required_u64(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
) -> Result<u64> {
    v.get(key)
        .and_then(Value::as_u64)
        .ok_or_else(|| property(element, index, key))
}

pub(super) fn optional_u64(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
) -> Result<Option<u64>> {
    match v.get(key) {
        None => Ok(None),
        Some(x) => x
            .as_u64()
            .map(Some)
            .ok_or_else(|| property(element, index, key)),
    }
}

pub(super) fn reference(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
    count: usize,
) -> Result<Option<usize>> {
    match optional_u64(v, element, index, key)? {
        None => Ok(None),
        Some(value) if value < count as u64 => Ok(Some(value as usize)),
        Some(value) => Err(glb_error(GlbErrorKind::Reference {
            element,
            index,
            property: key,
            value,
            count,
        })),
    }
}

pub(super) fn floats(
    v: &Value,
    element: &'static str,
    index: usize,
    key: &'static str,
) -> Result<Option<Vec<f64>>> {
    match v.get(key) {
        None => Ok(None),
        Some(Value::Array(a)) => a
            .iter()
            .map(|x| x.as_f64().ok_or_else(|| property(element, index, key)))
            .collect::<Result<_>>()
            .map(Some),
        Some(_) => Err(property(element, index, key)),
    }
}
