//! The texture-array layers an entry point indexes with constants, for checking layer counts.

use super::*;

/// The highest constant layer index each global texture is loaded or stored with, in `entry`
/// and every function it calls.
pub(super) fn constant_layers(
    module: &Module,
    entry: &naga::Function,
) -> HashMap<Handle<naga::GlobalVariable>, u32> {
    use naga::{Expression, Statement};
    let mut highest = HashMap::new();
    let mut seen = HashSet::new();
    let mut pending = vec![entry];
    while let Some(function) = pending.pop() {
        let exprs = &function.expressions;
        let mut note = |image: Handle<Expression>, index: Option<Handle<Expression>>| {
            let Expression::GlobalVariable(global) = exprs[image] else {
                return;
            };
            let Some(layer) = index.and_then(|i| constant_u32(module, exprs, i)) else {
                return;
            };
            let slot = highest.entry(global).or_insert(layer);
            *slot = (*slot).max(layer);
        };
        for (_, e) in exprs.iter() {
            if let Expression::ImageLoad {
                image, array_index, ..
            } = *e
            {
                note(image, array_index);
            }
        }
        // Statements nest (if, loop, switch); walk them with an explicit stack.
        let mut blocks = vec![&function.body];
        while let Some(block) = blocks.pop() {
            for statement in block.iter() {
                match statement {
                    Statement::ImageStore {
                        image, array_index, ..
                    } => note(*image, *array_index),
                    Statement::Call { function, .. } if seen.insert(*function) => {
                        pending.push(&module.functions[*function]);
                    }
                    Statement::Block(b) => blocks.push(b),
                    Statement::If { accept, reject, .. } => {
                        blocks.push(accept);
                        blocks.push(reject);
                    }
                    Statement::Loop {
                        body, continuing, ..
                    } => {
                        blocks.push(body);
                        blocks.push(continuing);
                    }
                    Statement::Switch { cases, .. } => blocks.extend(cases.iter().map(|c| &c.body)),
                    _ => {}
                }
            }
        }
    }
    highest
}

/// The value of a constant integer expression (a literal or a named `const`), if it is one.
pub(super) fn constant_u32(
    module: &Module,
    exprs: &naga::Arena<naga::Expression>,
    e: Handle<naga::Expression>,
) -> Option<u32> {
    use naga::{Expression, Literal};
    let literal = |e: &Expression| match *e {
        Expression::Literal(l) => Some(l),
        _ => None,
    };
    let value = match exprs[e] {
        Expression::Constant(c) => literal(&module.global_expressions[module.constants[c].init])?,
        ref other => literal(other)?,
    };
    match value {
        Literal::U32(v) => Some(v),
        Literal::I32(v) => u32::try_from(v).ok(),
        Literal::AbstractInt(v) => u32::try_from(v).ok(),
        _ => None,
    }
}
