//! Turning wgpu's errors into values: by default wgpu hands them to an uncaptured-error
//! handler that panics, which a bad shader or an oversized resource must never cause.

use std::error::Error as _;

/// Runs `f` with validation, out-of-memory and internal errors captured; `Err` holds the first
/// error's description with its causes. Internal errors matter too: a pipeline the backend
/// fails to compile is reported as one.
pub fn capture_errors<T>(device: &wgpu::Device, f: impl FnOnce() -> T) -> Result<T, String> {
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out_of_memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let internal = device.push_error_scope(wgpu::ErrorFilter::Internal);
    let value = f();
    // Scopes pop innermost first.
    let errors = [
        pollster::block_on(internal.pop()),
        pollster::block_on(out_of_memory.pop()),
        pollster::block_on(validation.pop()),
    ];
    match errors.into_iter().flatten().next() {
        Some(error) => Err(describe(&error)),
        None => Ok(value),
    }
}

/// The error and each cause not already spelled out by the one before, on one line each.
fn describe(error: &wgpu::Error) -> String {
    let mut text = error.to_string().trim().to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let line = cause.to_string();
        if !text.contains(line.trim()) {
            text.push_str("\n  ");
            text.push_str(line.trim());
        }
        source = cause.source();
    }
    text
}
