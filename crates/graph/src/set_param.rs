//! Overriding one instance's param from the command line: `--set INSTANCE.PARAM=VALUE`.

use super::error::GraphError;
use super::id::{Id, PassIndex};
use super::load::LoadedGraph;
use super::param::{ParamType, ParamValue};
use super::provided::ProvidedSet;

/// Parses `VALUE` as the param's type: `0.5`, `3`, `-1`, `true`, or comma-separated vectors
/// such as `0.1,0.1,0.1`.
pub fn parse_value(ty: ParamType, text: &str) -> Result<ParamValue, String> {
    let floats = |n: usize| -> Result<Vec<f32>, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        if parts.len() != n {
            return Err(format!(
                "expected {n} comma-separated numbers, got '{text}'"
            ));
        }
        parts
            .iter()
            .map(|p| {
                p.parse::<f32>()
                    .map_err(|_| format!("'{p}' is not a number"))
            })
            .collect()
    };
    let bad = |what: &str| format!("'{text}' is not {what}");
    Ok(match ty {
        ParamType::F32 => ParamValue::F32(text.trim().parse().map_err(|_| bad("an f32"))?),
        ParamType::U32 => ParamValue::U32(text.trim().parse().map_err(|_| bad("a u32"))?),
        ParamType::I32 => ParamValue::I32(text.trim().parse().map_err(|_| bad("an i32"))?),
        ParamType::Bool => ParamValue::Bool(text.trim().parse().map_err(|_| bad("true or false"))?),
        ParamType::Vec2 => {
            let v = floats(2)?;
            ParamValue::Vec2(v[0], v[1])
        }
        ParamType::Vec3 => {
            let v = floats(3)?;
            ParamValue::Vec3(v[0], v[1], v[2])
        }
        ParamType::Vec4 => {
            let v = floats(4)?;
            ParamValue::Vec4(v[0], v[1], v[2], v[3])
        }
    })
}

/// Applies `INSTANCE.PARAM=VALUE` to a loaded graph, before it is compiled; `PARAM=VALUE` sets
/// it on every instance whose pass has the param.
pub fn set_param(
    graph: &mut LoadedGraph,
    assignment: &str,
    provided: &ProvidedSet,
) -> Result<(), GraphError> {
    let invalid = |reason: String| GraphError::InvalidSetting {
        graph: graph.file.clone(),
        setting: assignment.to_string(),
        reason,
    };
    let Some((target, text)) = assignment.split_once('=') else {
        return Err(invalid(
            "expected INSTANCE.PARAM=VALUE or PARAM=VALUE".into(),
        ));
    };
    let target = target.trim();
    let (instance, param) = match target.split_once('.') {
        Some((instance, param)) => (Some(instance), param),
        None => (None, target),
    };
    let instances: Vec<PassIndex> = match instance {
        Some(instance) => {
            let Some(index) = graph.decl.passes.position(|p| p.name == instance) else {
                let names: Vec<&str> = graph.decl.passes.iter().map(|p| p.name.as_str()).collect();
                return Err(invalid(format!(
                    "no pass instance '{instance}' (instances: {})",
                    names.join(", ")
                )));
            };
            vec![index]
        }
        None => {
            let having: Vec<PassIndex> = PassIndex::all(graph.decl.passes.len())
                .filter(|&i| {
                    graph.passes[&graph.decl.passes[i].pass]
                        .params(provided)
                        .contains_key(param)
                })
                .collect();
            if having.is_empty() {
                return Err(invalid(format!(
                    "no pass of the graph has a param '{param}'"
                )));
            }
            having
        }
    };
    for index in instances {
        let value = instance_value(graph, index, param, text, provided).map_err(&invalid)?;
        graph.decl.passes[index]
            .params
            .insert(param.to_string(), value);
    }
    Ok(())
}

/// `text` as a value of instance `index`'s param `param`, checked against its type and range.
fn instance_value(
    graph: &LoadedGraph,
    index: PassIndex,
    param: &str,
    text: &str,
    provided: &ProvidedSet,
) -> Result<ParamValue, String> {
    let instance = &graph.decl.passes[index].name;
    let pass = &graph.passes[&graph.decl.passes[index].pass];
    let declared = pass.params(provided);
    let Some(default) = declared.get(param) else {
        let names: Vec<&str> = declared.keys().map(String::as_str).collect();
        return Err(format!(
            "pass '{instance}' has no param '{param}' (params: {})",
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            }
        ));
    };
    let value = parse_value(default.ty(), text)
        .map_err(|e| format!("{e} (param type {})", default.ty()))?;
    if !value.is_finite() {
        return Err(format!(
            "'{text}' is not finite; a param must be a finite number"
        ));
    }
    if let Some(&(min, max)) = pass.decl.ranges.get(param)
        && !value.within((min, max))
    {
        return Err(format!(
            "'{text}' is outside the param's range {min} to {max} (declared in {})",
            pass.file.display()
        ));
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_and_scalars_parse_by_the_declared_type() {
        assert_eq!(
            parse_value(ParamType::Vec3, "0.1, 0.2,0.3").unwrap(),
            ParamValue::Vec3(0.1, 0.2, 0.3)
        );
        assert_eq!(
            parse_value(ParamType::U32, "16").unwrap(),
            ParamValue::U32(16)
        );
        assert!(parse_value(ParamType::U32, "-1").is_err());
        assert!(parse_value(ParamType::Vec3, "1,2").is_err());
        assert!(parse_value(ParamType::F32, "fast").is_err());
    }
}
