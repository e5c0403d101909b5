//! naga types and literals as param types and values.

use super::*;

pub(super) fn uniform_field_type(inner: &TypeInner) -> Option<ParamType> {
    match *inner {
        TypeInner::Scalar(Scalar::F32) => Some(ParamType::F32),
        TypeInner::Scalar(Scalar::U32) => Some(ParamType::U32),
        TypeInner::Scalar(Scalar::I32) => Some(ParamType::I32),
        TypeInner::Vector {
            size,
            scalar: Scalar::F32,
        } => Some(match size {
            VectorSize::Bi => ParamType::Vec2,
            VectorSize::Tri => ParamType::Vec3,
            VectorSize::Quad => ParamType::Vec4,
        }),
        _ => None,
    }
}

/// A literal override default as a param value (the override types: bool, f32, u32, i32).
pub(super) fn literal_value(literal: naga::Literal) -> Option<ParamValue> {
    match literal {
        naga::Literal::Bool(b) => Some(ParamValue::Bool(b)),
        naga::Literal::F32(f) => Some(ParamValue::F32(f)),
        naga::Literal::U32(u) => Some(ParamValue::U32(u)),
        naga::Literal::I32(i) => Some(ParamValue::I32(i)),
        _ => None,
    }
}

pub(super) fn override_type(inner: &TypeInner) -> Option<ParamType> {
    match *inner {
        TypeInner::Scalar(Scalar::BOOL) => Some(ParamType::Bool),
        TypeInner::Scalar(Scalar::F32) => Some(ParamType::F32),
        TypeInner::Scalar(Scalar::U32) => Some(ParamType::U32),
        TypeInner::Scalar(Scalar::I32) => Some(ParamType::I32),
        _ => None,
    }
}
