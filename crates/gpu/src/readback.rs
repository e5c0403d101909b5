//! Blocking reads of GPU buffers, for tests, image output and timing.

use std::sync::mpsc;

/// Maps `buffer` (which needs `MAP_READ`) once the work submitted so far is done and copies
/// its first `len` bytes out. Blocks the calling thread. The whole buffer is mapped because
/// mapped ranges must be 4-byte multiples and `len` need not be.
pub fn read_mapped(
    device: &wgpu::Device,
    buffer: &wgpu::Buffer,
    len: u64,
) -> Result<Vec<u8>, String> {
    let (sender, receiver) = mpsc::channel();
    buffer.map_async(wgpu::MapMode::Read, .., move |result| {
        // The receiver only disappears if this function already returned.
        let _ = sender.send(result);
    });
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| format!("waiting for the GPU failed: {e}"))?;
    match receiver.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(format!("cannot map the readback buffer: {e}")),
        Err(_) => return Err("the GPU never finished mapping the readback buffer".into()),
    }
    let bytes = buffer
        .get_mapped_range(..)
        .map(|view| view[..view.len().min(len as usize)].to_vec())
        .map_err(|e| format!("cannot view the readback buffer: {e}"));
    buffer.unmap();
    bytes
}
