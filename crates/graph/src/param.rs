//! Typed pass parameters: declared with defaults in a pass, overridden per instance in a graph.

use serde::Deserialize;
use std::fmt;

/// A parameter value as written in RON, e.g. `F32(0.5)` or `Vec3(1.0, 0.0, 0.0)`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub enum ParamValue {
    F32(f32),
    U32(u32),
    I32(i32),
    Bool(bool),
    Vec2(f32, f32),
    Vec3(f32, f32, f32),
    Vec4(f32, f32, f32, f32),
}

/// The type of a parameter, shared by RON values, uniform fields and override constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamType {
    F32,
    U32,
    I32,
    Bool,
    Vec2,
    Vec3,
    Vec4,
}

impl ParamValue {
    /// The value as WGSL writes it (`4u`, `-1i`, `0.5`, `true`): for messages.
    pub fn wgsl_literal(&self) -> String {
        match self {
            ParamValue::F32(v) => format!("{v:?}"),
            ParamValue::U32(v) => format!("{v}u"),
            ParamValue::I32(v) => format!("{v}i"),
            ParamValue::Bool(v) => v.to_string(),
            ParamValue::Vec2(..) | ParamValue::Vec3(..) | ParamValue::Vec4(..) => {
                format!("{self:?}")
            }
        }
    }

    pub fn ty(&self) -> ParamType {
        match self {
            ParamValue::F32(_) => ParamType::F32,
            ParamValue::U32(_) => ParamType::U32,
            ParamValue::I32(_) => ParamType::I32,
            ParamValue::Bool(_) => ParamType::Bool,
            ParamValue::Vec2(..) => ParamType::Vec2,
            ParamValue::Vec3(..) => ParamType::Vec3,
            ParamValue::Vec4(..) => ParamType::Vec4,
        }
    }

    /// Whether every float component is finite: NaN or infinity (also what RON makes of a
    /// literal beyond f32's range, e.g. 1e39) would poison every pixel the param touches.
    pub fn is_finite(&self) -> bool {
        match *self {
            ParamValue::F32(x) => x.is_finite(),
            ParamValue::Vec2(a, b) => a.is_finite() && b.is_finite(),
            ParamValue::Vec3(a, b, c) => [a, b, c].iter().all(|v| v.is_finite()),
            ParamValue::Vec4(a, b, c, d) => [a, b, c, d].iter().all(|v| v.is_finite()),
            ParamValue::U32(_) | ParamValue::I32(_) | ParamValue::Bool(_) => true,
        }
    }

    /// The value of a scalar param as a number (for its range); `None` for bools and vectors.
    pub fn scalar(&self) -> Option<f64> {
        match *self {
            ParamValue::F32(x) => Some(f64::from(x)),
            ParamValue::U32(x) => Some(f64::from(x)),
            ParamValue::I32(x) => Some(f64::from(x)),
            _ => None,
        }
    }

    /// Whether the value lies in `range` (min, max inclusive); non-scalars always do.
    pub fn within(&self, (min, max): (f64, f64)) -> bool {
        self.scalar().is_none_or(|v| min <= v && v <= max)
    }

    /// Little-endian bytes as WGSL lays the value out in a uniform block.
    pub fn to_le_bytes(&self) -> Vec<u8> {
        let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect();
        match *self {
            ParamValue::F32(x) => x.to_le_bytes().to_vec(),
            ParamValue::U32(x) => x.to_le_bytes().to_vec(),
            ParamValue::I32(x) => x.to_le_bytes().to_vec(),
            ParamValue::Bool(x) => u32::from(x).to_le_bytes().to_vec(),
            ParamValue::Vec2(a, b) => floats(&[a, b]),
            ParamValue::Vec3(a, b, c) => floats(&[a, b, c]),
            ParamValue::Vec4(a, b, c, d) => floats(&[a, b, c, d]),
        }
    }

    /// The value as a pipeline-override constant (WebGPU passes them all as f64).
    pub fn as_override(&self) -> Option<f64> {
        match *self {
            ParamValue::F32(x) => Some(f64::from(x)),
            ParamValue::U32(x) => Some(f64::from(x)),
            ParamValue::I32(x) => Some(f64::from(x)),
            ParamValue::Bool(x) => Some(if x { 1.0 } else { 0.0 }),
            _ => None,
        }
    }
}

impl fmt::Display for ParamType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ParamType::F32 => "F32 (f32)",
            ParamType::U32 => "U32 (u32)",
            ParamType::I32 => "I32 (i32)",
            ParamType::Bool => "Bool (bool)",
            ParamType::Vec2 => "Vec2 (vec2<f32>)",
            ParamType::Vec3 => "Vec3 (vec3<f32>)",
            ParamType::Vec4 => "Vec4 (vec4<f32>)",
        })
    }
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::F32(x) => write!(f, "F32({x:?})"),
            ParamValue::U32(x) => write!(f, "U32({x})"),
            ParamValue::I32(x) => write!(f, "I32({x})"),
            ParamValue::Bool(x) => write!(f, "Bool({x})"),
            ParamValue::Vec2(a, b) => write!(f, "Vec2({a:?}, {b:?})"),
            ParamValue::Vec3(a, b, c) => write!(f, "Vec3({a:?}, {b:?}, {c:?})"),
            ParamValue::Vec4(a, b, c, d) => write!(f, "Vec4({a:?}, {b:?}, {c:?}, {d:?})"),
        }
    }
}
