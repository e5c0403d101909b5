//! A pass's shader specialised to its override values before the driver sees it.
//!
//! wgpu substitutes override values (naga's `process_overrides`) but keeps every branch, so a
//! condition such as `scene_has_kind(MATERIAL_CONDUCTOR)` that the scene made `false` still
//! reaches the driver with the code it guards. lavapipe inlines every call before it removes
//! dead branches, so it translated and optimised each unused material model once per call
//! site: on the Cornell box, 0.5-0.6 s of CPU to create the path pass's pipeline against
//! 0.15-0.19 s specialised here, most of the start-up (docs/benchmark-history.md). Here the
//! values are substituted as wgpu would, every `if` whose condition is then known is replaced
//! by the branch taken (conditions are followed through `&&`/`||`, which naga lowers to
//! local variables, and through calls of functions that return a known value), code after a
//! `return`, `break` or `continue` is dropped, and what is left unused is compacted away.
//!
//! Anything this cannot do is an error saying which step failed; the caller then hands wgpu
//! the WGSL as written, so errors are still reported as wgpu reports them (reflection has
//! already checked the shader and named its file and line), and reports the fallback: a pass
//! built from the WGSL renders the same image, but its pipeline is slower to create
//! (tests/specialise_shipped.rs checks every shipped pass specialises).

use naga::back::pipeline_constants::process_overrides;
use naga::compact::{KeepUnused, compact};
use naga::valid::{ValidationFlags, Validator};
use naga::{
    BinaryOperator, Block, Expression, Function, Handle, Literal, LocalVariable, Module,
    ShaderStage, Statement, UnaryOperator,
};
use passgraph_graph::reflect::{NAGA_STACK_BYTES, capabilities};
use passgraph_graph::shader_source::ValidShader;
use std::collections::{HashMap, HashSet};

/// The module wgpu would compile for `entry` (every entry point when `None`) with `constants`
/// substituted, its dead branches removed; an error naming the step that failed. Parses and
/// validates `code` first; [`specialise_validated`] starts from a module reflection already
/// validated.
pub fn specialise(
    code: &str,
    entry: Option<(ShaderStage, &str)>,
    constants: &[(&str, f64)],
) -> Result<Module, String> {
    on_naga_thread(|| {
        let module = naga::front::wgsl::parse_str(code)
            .map_err(|e| format!("naga cannot parse the WGSL: {e}"))?;
        let info = validator()
            .validate(&module)
            .map_err(|e| format!("naga does not validate the WGSL: {e}"))?;
        specialise_here(&ValidShader { module, info }, entry, constants)
    })
}

/// [`specialise`] from the module reflection parsed and validated (`ShaderSource::validated`):
/// no second parse.
pub fn specialise_validated(
    shader: &ValidShader,
    entry: Option<(ShaderStage, &str)>,
    constants: &[(&str, f64)],
) -> Result<Module, String> {
    on_naga_thread(|| specialise_here(shader, entry, constants))
}

/// Runs `f` on a thread with reflection's stack (naga recurses per operand of long
/// expressions); a panic inside naga is one more thing to leave to the WGSL path.
fn on_naga_thread<T: Send>(f: impl FnOnce() -> Result<T, String> + Send) -> Result<T, String> {
    std::thread::scope(|scope| {
        std::thread::Builder::new()
            .name("naga specialise".into())
            .stack_size(NAGA_STACK_BYTES)
            .spawn_scoped(scope, f)
            .map_err(|e| format!("cannot start naga's thread: {e}"))?
            .join()
            .map_err(|_| "naga panicked".to_string())?
    })
}

fn specialise_here(
    shader: &ValidShader,
    entry: Option<(ShaderStage, &str)>,
    constants: &[(&str, f64)],
) -> Result<Module, String> {
    let constants: naga::back::PipelineConstants = constants
        .iter()
        .map(|(name, value)| (name.to_string(), *value))
        .collect();
    let (module, _) = process_overrides(&shader.module, &shader.info, entry, &constants)
        .map_err(|e| format!("naga cannot substitute the override values: {e}"))?;
    let mut module = module.into_owned();
    fold_module(&mut module);
    compact(&mut module, KeepUnused::No);
    // The result must be as valid as its source: wgpu validates it again, but an error there
    // would name no file; the WGSL path reports it instead.
    validator()
        .validate(&module)
        .map_err(|e| format!("the specialised module does not validate: {e}"))?;
    Ok(module)
}

/// The framework's one capability policy, as reflection's (passgraph-graph).
fn validator() -> Validator {
    Validator::new(ValidationFlags::all(), capabilities())
}

/// A value known before the shader runs. Floats are not followed: no specialising condition
/// needs them.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Value {
    Bool(bool),
    U32(u32),
    I32(i32),
}

impl Value {
    fn of(literal: &Literal) -> Option<Value> {
        match *literal {
            Literal::Bool(b) => Some(Value::Bool(b)),
            Literal::U32(u) => Some(Value::U32(u)),
            Literal::I32(i) => Some(Value::I32(i)),
            _ => None,
        }
    }
}

/// Removes the dead branches of every function and entry point.
fn fold_module(module: &mut Module) {
    // Calls are evaluated on the unfolded functions: folding does not change what they return.
    let (functions, entry_points) = {
        let mut folder = Folder {
            module,
            returns: HashMap::new(),
        };
        let functions: Vec<(Handle<Function>, Function)> = module
            .functions
            .iter()
            .map(|(h, f)| (h, folder.fold_function(f)))
            .collect();
        let entry_points: Vec<Function> = module
            .entry_points
            .iter()
            .map(|ep| folder.fold_function(&ep.function))
            .collect();
        (functions, entry_points)
    };
    for (h, f) in functions {
        module.functions[h] = f;
    }
    for (ep, f) in module.entry_points.iter_mut().zip(entry_points) {
        ep.function = f;
    }
}

struct Folder<'a> {
    module: &'a Module,
    /// What a function returns for known (or unknown: `None`) arguments, when it is known.
    returns: HashMap<Call, Option<Value>>,
}

/// One walk through one function body.
struct Walk<'f> {
    function: &'f Function,
    args: &'f [Option<Value>],
    /// Emitted expressions whose value is known.
    values: HashMap<Handle<Expression>, Value>,
    /// Call results, evaluated on demand: (callee, argument values).
    calls: HashMap<Handle<Expression>, Call>,
    /// The values of the `return` statements reached (`None`: unknown).
    returned: Vec<Option<Value>>,
}

/// A callee and the values of its arguments (`None`: unknown).
type Call = (Handle<Function>, Vec<Option<Value>>);

/// Local variables whose value is known at a point of the walk.
type Vars = HashMap<Handle<LocalVariable>, Value>;

impl Folder<'_> {
    fn fold_function(&mut self, function: &Function) -> Function {
        let mut body = function.body.clone();
        let mut walk = Walk::new(function, &[]);
        let mut vars = self.initial_vars(&mut walk);
        self.walk_block(&mut walk, &mut body, &mut vars);
        let mut folded = function.clone();
        folded.body = body;
        prune_named_expressions(&mut folded);
        folded
    }

    fn initial_vars(&mut self, walk: &mut Walk) -> Vars {
        let function = walk.function;
        function
            .local_variables
            .iter()
            .filter_map(|(h, var)| Some((h, self.eval(walk, var.init?)?)))
            .collect()
    }

    /// What `function` returns for these arguments, if every `return` reached agrees.
    fn call_value(
        &mut self,
        function: Handle<Function>,
        args: Vec<Option<Value>>,
    ) -> Option<Value> {
        let key = (function, args);
        if let Some(value) = self.returns.get(&key) {
            return *value;
        }
        let module = self.module;
        let callee = &module.functions[function];
        let scalar = callee
            .result
            .as_ref()
            .is_some_and(|r| matches!(self.module.types[r.ty].inner, naga::TypeInner::Scalar(_)));
        let value = if scalar {
            let mut body = callee.body.clone();
            let mut walk = Walk::new(callee, &key.1);
            let mut vars = self.initial_vars(&mut walk);
            self.walk_block(&mut walk, &mut body, &mut vars);
            match walk.returned.split_first() {
                Some((first, rest)) if rest.iter().all(|r| r == first) => *first,
                _ => None,
            }
        } else {
            None
        };
        self.returns.insert(key, value);
        value
    }

    /// Folds `block` in place; whether it always ends in a jump (`return`, `break`, ...).
    fn walk_block(&mut self, walk: &mut Walk, block: &mut Block, vars: &mut Vars) -> bool {
        let old = std::mem::take(block);
        let mut jumps = false;
        for (statement, span) in old.span_into_iter() {
            if jumps {
                // Unreachable.
                continue;
            }
            let statement = match statement {
                Statement::Emit(range) => {
                    for h in range.clone() {
                        if let Some(v) = self.eval_emitted(walk, h, vars) {
                            walk.values.insert(h, v);
                        }
                    }
                    Statement::Emit(range)
                }
                Statement::Block(mut inner) => {
                    jumps = self.walk_block(walk, &mut inner, vars);
                    Statement::Block(inner)
                }
                Statement::If {
                    condition,
                    mut accept,
                    mut reject,
                } => match self.eval(walk, condition) {
                    Some(Value::Bool(taken)) => {
                        // The branch taken, spliced in (its statements' expressions are not
                        // used after it, so widening their scope changes nothing).
                        let mut branch = if taken { accept } else { reject };
                        jumps = self.walk_block(walk, &mut branch, vars);
                        for (s, span) in branch.span_into_iter() {
                            block.push(s, span);
                        }
                        continue;
                    }
                    _ => {
                        let mut vars_reject = vars.clone();
                        let accept_jumps = self.walk_block(walk, &mut accept, vars);
                        let reject_jumps = self.walk_block(walk, &mut reject, &mut vars_reject);
                        if accept_jumps {
                            *vars = vars_reject;
                        } else if !reject_jumps {
                            vars.retain(|h, v| vars_reject.get(h) == Some(v));
                        }
                        jumps = accept_jumps && reject_jumps;
                        Statement::If {
                            condition,
                            accept,
                            reject,
                        }
                    }
                },
                Statement::Switch {
                    selector,
                    mut cases,
                } => {
                    // Each case may be entered by falling through: it starts knowing only
                    // what no case changes.
                    let mut stored = HashSet::new();
                    for case in &cases {
                        stored_vars(walk.function, &case.body, &mut stored);
                    }
                    vars.retain(|h, _| !stored.contains(h));
                    for case in &mut cases {
                        self.walk_block(walk, &mut case.body, &mut vars.clone());
                    }
                    Statement::Switch { selector, cases }
                }
                Statement::Loop {
                    mut body,
                    mut continuing,
                    break_if,
                } => {
                    // Any iteration starts knowing only what the loop does not change.
                    let mut stored = HashSet::new();
                    stored_vars(walk.function, &body, &mut stored);
                    stored_vars(walk.function, &continuing, &mut stored);
                    vars.retain(|h, _| !stored.contains(h));
                    self.walk_block(walk, &mut body, &mut vars.clone());
                    self.walk_block(walk, &mut continuing, &mut vars.clone());
                    Statement::Loop {
                        body,
                        continuing,
                        break_if,
                    }
                }
                Statement::Return { value } => {
                    let v = value.and_then(|h| self.eval(walk, h));
                    walk.returned.push(v);
                    jumps = true;
                    Statement::Return { value }
                }
                s @ (Statement::Break | Statement::Continue | Statement::Kill) => {
                    jumps = true;
                    s
                }
                Statement::Store { pointer, value } => {
                    match walk.function.expressions[pointer] {
                        Expression::LocalVariable(var) => match self.eval(walk, value) {
                            Some(v) => {
                                vars.insert(var, v);
                            }
                            None => {
                                vars.remove(&var);
                            }
                        },
                        _ => {
                            if let Some(var) = local_root(walk.function, pointer) {
                                vars.remove(&var);
                            }
                        }
                    }
                    Statement::Store { pointer, value }
                }
                Statement::Call {
                    function,
                    arguments,
                    result,
                } => {
                    // A callee may write through a pointer to a local.
                    for &a in &arguments {
                        if let Some(var) = local_root(walk.function, a) {
                            vars.remove(&var);
                        }
                    }
                    if let Some(result) = result {
                        let args = arguments.iter().map(|&a| self.eval(walk, a)).collect();
                        walk.calls.insert(result, (function, args));
                    }
                    Statement::Call {
                        function,
                        arguments,
                        result,
                    }
                }
                s => {
                    // Atomics and the like write through pointers too.
                    let mut stored = HashSet::new();
                    stored_vars_of(walk.function, &s, &mut stored);
                    vars.retain(|h, _| !stored.contains(h));
                    s
                }
            };
            block.push(statement, span);
        }
        jumps
    }

    /// The value of `h` where the walk stands, if known.
    fn eval(&mut self, walk: &mut Walk, h: Handle<Expression>) -> Option<Value> {
        if let Some(v) = walk.values.get(&h) {
            return Some(*v);
        }
        match walk.function.expressions[h] {
            Expression::Literal(ref l) => Value::of(l),
            Expression::Constant(c) => self.eval_global(self.module.constants[c].init),
            Expression::FunctionArgument(i) => walk.args.get(i as usize).copied().flatten(),
            Expression::CallResult(_) => {
                let (function, args) = walk.calls.get(&h)?.clone();
                let v = self.call_value(function, args)?;
                walk.values.insert(h, v);
                Some(v)
            }
            // Emitted expressions were evaluated at their emission.
            _ => None,
        }
    }

    /// The value of an expression as it is emitted (`vars`: the locals known there).
    fn eval_emitted(
        &mut self,
        walk: &mut Walk,
        h: Handle<Expression>,
        vars: &Vars,
    ) -> Option<Value> {
        match walk.function.expressions[h] {
            Expression::Load { pointer } => match walk.function.expressions[pointer] {
                Expression::LocalVariable(var) => vars.get(&var).copied(),
                _ => None,
            },
            Expression::Unary { op, expr } => unary(op, self.eval(walk, expr)?),
            Expression::Binary { op, left, right } => {
                let left = self.eval(walk, left)?;
                // `false && x`, `true || x`: x need not be known.
                match (op, left) {
                    (BinaryOperator::LogicalAnd, Value::Bool(false)) => return Some(left),
                    (BinaryOperator::LogicalOr, Value::Bool(true)) => return Some(left),
                    _ => {}
                }
                binary(op, left, self.eval(walk, right)?)
            }
            Expression::Select {
                condition,
                accept,
                reject,
            } => match self.eval(walk, condition)? {
                Value::Bool(true) => self.eval(walk, accept),
                Value::Bool(false) => self.eval(walk, reject),
                _ => None,
            },
            _ => self.eval(walk, h),
        }
    }

    fn eval_global(&self, h: Handle<Expression>) -> Option<Value> {
        match self.module.global_expressions[h] {
            Expression::Literal(ref l) => Value::of(l),
            Expression::Constant(c) => self.eval_global(self.module.constants[c].init),
            _ => None,
        }
    }
}

impl<'f> Walk<'f> {
    fn new(function: &'f Function, args: &'f [Option<Value>]) -> Walk<'f> {
        Walk {
            function,
            args,
            values: HashMap::new(),
            calls: HashMap::new(),
            returned: Vec::new(),
        }
    }
}

fn unary(op: UnaryOperator, v: Value) -> Option<Value> {
    Some(match (op, v) {
        (UnaryOperator::LogicalNot, Value::Bool(b)) => Value::Bool(!b),
        (UnaryOperator::BitwiseNot, Value::U32(u)) => Value::U32(!u),
        (UnaryOperator::BitwiseNot, Value::I32(i)) => Value::I32(!i),
        (UnaryOperator::Negate, Value::I32(i)) => Value::I32(i.wrapping_neg()),
        _ => return None,
    })
}

fn binary(op: BinaryOperator, a: Value, b: Value) -> Option<Value> {
    use BinaryOperator as B;
    use Value::{Bool, I32, U32};
    Some(match (a, b) {
        (Bool(a), Bool(b)) => Bool(match op {
            B::LogicalAnd | B::And => a && b,
            B::LogicalOr | B::InclusiveOr => a || b,
            B::Equal => a == b,
            B::NotEqual | B::ExclusiveOr => a != b,
            _ => return None,
        }),
        (U32(a), U32(b)) => match op {
            B::Add => U32(a.wrapping_add(b)),
            B::Subtract => U32(a.wrapping_sub(b)),
            B::Multiply => U32(a.wrapping_mul(b)),
            B::And => U32(a & b),
            B::InclusiveOr => U32(a | b),
            B::ExclusiveOr => U32(a ^ b),
            B::ShiftLeft => U32(a.checked_shl(b)?),
            B::ShiftRight => U32(a.checked_shr(b)?),
            _ => Bool(compare(op, a, b)?),
        },
        (I32(a), I32(b)) => match op {
            B::Add => I32(a.wrapping_add(b)),
            B::Subtract => I32(a.wrapping_sub(b)),
            B::Multiply => I32(a.wrapping_mul(b)),
            B::And => I32(a & b),
            B::InclusiveOr => I32(a | b),
            B::ExclusiveOr => I32(a ^ b),
            _ => Bool(compare(op, a, b)?),
        },
        // Shifts of signed values by an unsigned amount.
        (I32(a), U32(b)) => match op {
            B::ShiftLeft => I32(a.checked_shl(b)?),
            B::ShiftRight => I32(a.checked_shr(b)?),
            _ => return None,
        },
        _ => return None,
    })
}

fn compare<T: PartialOrd>(op: BinaryOperator, a: T, b: T) -> Option<bool> {
    use BinaryOperator as B;
    Some(match op {
        B::Equal => a == b,
        B::NotEqual => a != b,
        B::Less => a < b,
        B::LessEqual => a <= b,
        B::Greater => a > b,
        B::GreaterEqual => a >= b,
        _ => return None,
    })
}

/// The local variable a pointer expression points into, if any.
fn local_root(function: &Function, mut h: Handle<Expression>) -> Option<Handle<LocalVariable>> {
    loop {
        match function.expressions[h] {
            Expression::LocalVariable(var) => return Some(var),
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => h = base,
            _ => return None,
        }
    }
}

/// Adds the locals `block` may write (stores, calls given pointers, atomics) to `out`.
fn stored_vars(function: &Function, block: &Block, out: &mut HashSet<Handle<LocalVariable>>) {
    for statement in block.iter() {
        stored_vars_of(function, statement, out);
    }
}

fn stored_vars_of(
    function: &Function,
    statement: &Statement,
    out: &mut HashSet<Handle<LocalVariable>>,
) {
    let mut pointer = |h: Handle<Expression>| {
        if let Some(var) = local_root(function, h) {
            out.insert(var);
        }
    };
    match *statement {
        Statement::Block(ref b) => stored_vars(function, b, out),
        Statement::If {
            ref accept,
            ref reject,
            ..
        } => {
            stored_vars(function, accept, out);
            stored_vars(function, reject, out);
        }
        Statement::Switch { ref cases, .. } => {
            for case in cases {
                stored_vars(function, &case.body, out);
            }
        }
        Statement::Loop {
            ref body,
            ref continuing,
            ..
        } => {
            stored_vars(function, body, out);
            stored_vars(function, continuing, out);
        }
        Statement::Store { pointer: p, .. }
        | Statement::Atomic { pointer: p, .. }
        | Statement::WorkGroupUniformLoad { pointer: p, .. } => pointer(p),
        Statement::Call { ref arguments, .. } => arguments.iter().for_each(|&a| pointer(a)),
        Statement::RayQuery { query, .. } => pointer(query),
        _ => {}
    }
}

/// Drops names of expressions whose statement was removed (a name keeps its expression from
/// compaction, and an expression no statement produces must not survive).
fn prune_named_expressions(function: &mut Function) {
    let mut live = HashSet::new();
    live_expressions(&function.body, &mut live);
    let expressions = &function.expressions;
    function
        .named_expressions
        .retain(|h, _| expressions[*h].needs_pre_emit() || live.contains(h));
}

/// The expressions `block` emits or its statements produce.
fn live_expressions(block: &Block, out: &mut HashSet<Handle<Expression>>) {
    for statement in block.iter() {
        match *statement {
            Statement::Emit(ref range) => out.extend(range.clone()),
            Statement::Block(ref b) => live_expressions(b, out),
            Statement::If {
                ref accept,
                ref reject,
                ..
            } => {
                live_expressions(accept, out);
                live_expressions(reject, out);
            }
            Statement::Switch { ref cases, .. } => {
                for case in cases {
                    live_expressions(&case.body, out);
                }
            }
            Statement::Loop {
                ref body,
                ref continuing,
                ..
            } => {
                live_expressions(body, out);
                live_expressions(continuing, out);
            }
            Statement::Call {
                result: Some(r), ..
            }
            | Statement::Atomic {
                result: Some(r), ..
            }
            | Statement::WorkGroupUniformLoad { result: r, .. }
            | Statement::SubgroupBallot { result: r, .. }
            | Statement::SubgroupGather { result: r, .. }
            | Statement::SubgroupCollectiveOperation { result: r, .. } => {
                out.insert(r);
            }
            Statement::RayQuery {
                fun: naga::RayQueryFunction::Proceed { result },
                ..
            } => {
                out.insert(result);
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHADER: &str = r#"
override kinds: u32 = 0xffffffffu;
override deep: bool = true;
fn has(k: u32) -> bool { return (kinds & (1u << k)) != 0u; }
fn model_a(x: f32) -> f32 { return x * 2.0; }
fn model_b(x: f32) -> f32 { return x + 1.0; }
fn model_c(x: f32) -> f32 { return x - 1.0; }
fn model_d(x: f32) -> f32 { return x * 3.0; }
fn model_e(x: f32) -> f32 { return x * 5.0; }
@group(0) @binding(0) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(1)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    var x = out[id.x];
    if has(1u) && id.x > 3u { x = model_a(x); }
    if has(0u) || id.x == 7u { x = model_b(x); }
    // Known only on some paths: kept.
    var flag = false;
    if id.x > 2u { flag = true; }
    if flag { x = model_c(x); }
    // Changed inside the loop: kept.
    var go = true;
    loop {
        if go { x = model_d(x); }
        go = false;
        if id.x < 10u { break; }
    }
    if !deep {
        out[id.x] = x;
        return;
    }
    out[id.x] = model_e(x);
}
"#;

    fn functions(module: &Module) -> Vec<String> {
        let mut names: Vec<String> = module
            .functions
            .iter()
            .filter_map(|(_, f)| f.name.clone())
            .collect();
        names.sort();
        names
    }

    fn specialised(constants: &[(&str, f64)]) -> Module {
        specialise(SHADER, Some((ShaderStage::Compute, "main")), constants).unwrap()
    }

    #[test]
    fn branches_the_overrides_decide_are_removed() {
        // Only kind 0: model_a's branch is dead; model_b's is always taken; not deep: no model_e.
        let module = specialised(&[("kinds", 1.0), ("deep", 0.0)]);
        assert_eq!(functions(&module), ["has", "model_b", "model_c", "model_d"]);
        assert!(module.overrides.is_empty());
    }

    #[test]
    fn branches_the_overrides_leave_open_are_kept() {
        let module = specialised(&[("kinds", 2.0), ("deep", 1.0)]);
        assert_eq!(
            functions(&module),
            ["has", "model_a", "model_b", "model_c", "model_d", "model_e"]
        );
    }

    #[test]
    fn defaults_apply_to_overrides_not_given() {
        let module = specialised(&[]);
        assert_eq!(
            functions(&module),
            ["has", "model_a", "model_b", "model_c", "model_d", "model_e"]
        );
    }

    #[test]
    fn what_cannot_be_specialised_is_left_to_wgpu() {
        let e = specialise("fn main( {", None, &[]).unwrap_err();
        assert!(e.starts_with("naga cannot parse the WGSL"), "{e}");
        let e = specialise(
            SHADER,
            Some((ShaderStage::Compute, "main")),
            &[("nope", 1.0)],
        )
        .unwrap_err();
        assert!(
            e.starts_with("naga cannot substitute the override values"),
            "{e}"
        );
    }
}
