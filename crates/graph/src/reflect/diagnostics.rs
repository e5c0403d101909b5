//! Errors of naga's front end and validator as file:line messages, and the expression-size guard.

use super::*;

/// Rejects a statement with more than [`MAX_OPERATORS_PER_STATEMENT`] binary operators, or
/// brackets nested deeper than [`MAX_NESTING`], with the file and line. Counts operator
/// characters between `;`, `{` and `}`, outside comments: an over-estimate (`<=` counts
/// twice), which is fine for a bound this loose.
pub(super) fn check_expression_size(source: &ShaderSource) -> Result<(), GraphError> {
    let code = source.code.as_bytes();
    let mut start = 0;
    let mut operators = 0;
    let mut depth = 0usize;
    let mut i = 0;
    let error = |at: usize, message: String| {
        let (file, line, col) = source.locate(at);
        GraphError::Wgsl {
            file,
            line,
            col,
            message,
        }
    };
    while i < code.len() {
        match code[i] {
            b'/' if code.get(i + 1) == Some(&b'/') => {
                while i < code.len() && code[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if code.get(i + 1) == Some(&b'*') => {
                i += 2;
                while i < code.len() && !(code[i] == b'*' && code.get(i + 1) == Some(&b'/')) {
                    i += 1;
                }
                i += 2;
                continue;
            }
            b';' | b'{' | b'}' => {
                start = i + 1;
                operators = 0;
            }
            _ => {}
        }
        match code[i] {
            b'(' | b'[' | b'{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(error(
                        i,
                        format!(
                            "brackets and blocks nested more than {MAX_NESTING} deep; use intermediate `let`s or functions"
                        ),
                    ));
                }
            }
            b')' | b']' | b'}' => depth = depth.saturating_sub(1),
            b'+' | b'-' | b'*' | b'/' | b'%' | b'&' | b'|' | b'^' | b'<' | b'>' | b'=' | b'!' => {
                operators += 1;
                if operators > MAX_OPERATORS_PER_STATEMENT {
                    let at = start
                        + (code[start..]
                            .iter()
                            .take_while(|c| c.is_ascii_whitespace())
                            .count());
                    return Err(error(
                        at,
                        format!(
                            "this statement chains more than {MAX_OPERATORS_PER_STATEMENT} operators; split it into several statements"
                        ),
                    ));
                }
            }
            _ => {}
        }
        i += 1;
    }
    Ok(())
}

/// Where an error without a usable span is reported.
pub(super) fn start_of_main(source: &ShaderSource) -> (PathBuf, usize, usize) {
    (source.path.clone(), 1, 1)
}

pub(super) fn wgsl_error(location: (PathBuf, usize, usize), message: String) -> GraphError {
    let (file, line, col) = location;
    GraphError::Wgsl {
        file,
        line,
        col,
        message,
    }
}

/// Whether a span label says something the message does not.
pub(super) fn adds_information(message: &str, label: &str) -> bool {
    let label = label.trim();
    !label.is_empty() && label != "see msg" && !message.contains(label)
}

pub(super) fn parse_error(
    source: &ShaderSource,
    error: &naga::front::wgsl::ParseError,
) -> GraphError {
    let mut labels = error
        .labels()
        .filter_map(|(span, label)| Some((span.to_range()?, label)));
    let primary = labels.next();
    let mut message = error.message().to_string();
    if let Some((_, label)) = &primary {
        if adds_information(&message, label) {
            message.push_str(&format!(" ({})", label.trim()));
        }
    }
    // Secondary labels point elsewhere, possibly into another file (e.g. the previous
    // definition in an included library), so they carry their own location.
    for (range, label) in labels {
        if adds_information(&message, label) {
            let (file, line, col) = source.locate(range.start);
            message.push_str(&format!(
                "; {} at {}:{line}:{col}",
                label.trim(),
                file.display()
            ));
        }
    }
    for note in error.notes() {
        message.push_str(&format!("; note: {note}"));
    }
    let location = primary.map_or_else(
        || start_of_main(source),
        |(range, _)| source.locate(range.start),
    );
    wgsl_error(location, message)
}

pub(super) fn validation_error(
    source: &ShaderSource,
    error: &naga::WithSpan<ValidationError>,
) -> GraphError {
    // The top-level message only names the function or global; the cause says what is wrong.
    let mut message = error.to_string();
    let mut cause = error.source();
    while let Some(inner) = cause {
        message.push_str(&format!(": {inner}"));
        cause = inner.source();
    }
    // naga lists the enclosing item's span (a whole function) before the offending
    // expression's, so the first span that contains no other is the precise one.
    let spans: Vec<(Range<usize>, &str)> = error
        .spans()
        .filter_map(|(span, label)| Some((span.to_range()?, label.as_str())))
        .collect();
    let innermost = spans.iter().find(|(outer, _)| {
        !spans.iter().any(|(inner, _)| {
            inner != outer && outer.start <= inner.start && inner.end <= outer.end
        })
    });
    let location = match innermost {
        Some((range, label)) => {
            // Labels naming naga's IR ("naga::ir::Function [0]") mean nothing to users.
            if !label.starts_with("naga::") && adds_information(&message, label) {
                message.push_str(&format!(" ({})", label.trim()));
            }
            source.locate(range.start)
        }
        None => start_of_main(source),
    };
    wgsl_error(location, message)
}
