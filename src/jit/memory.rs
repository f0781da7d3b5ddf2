//! Executable memory near the program's own code (x86-64 Linux).
//!
//! x86-64 cores predict calls into, and returns from, code more than 4 GiB away from the
//! caller worse than near ones. Measured here: a native loop calling a one-load function
//! through a pointer takes 1.60 ns per call when the code lies within 64 MiB of the loop
//! and 2.22 ns when it lies 40 TiB away, which is where `mmap` puts a JIT's memory by
//! default (the program sits low in the address space, mappings high). For one-line
//! expressions that 0.6 ns was a third of the call.
//!
//! [`NearMemory`] maps the module's pages within ±1 GiB of this function's own code (so
//! of the solver calling it, in the same executable): it asks `mmap` for addresses below
//! the executable (the heap grows above it) and keeps a mapping only if it landed close
//! enough; when none does it takes any address (correct, only slower). Pages are
//! read-write while Cranelift writes them; [`finalize`](NearMemory::finalize) makes code
//! read-execute and constants read-only. x86 keeps instruction fetch coherent with
//! stores, so no cache flush is needed.

use cranelift_jit::{BranchProtection, JITMemoryKind, JITMemoryProvider};
use cranelift_module::{ModuleError, ModuleResult};
use std::io;

/// Smallest mapping (pages are committed only when touched).
const CHUNK: usize = 64 << 10;
/// How far from this code a mapping may land.
const REACH: usize = 1 << 30;
/// Distance between the addresses tried below the executable.
const STEP: usize = 32 << 20;

/// One mapping: pages of one kind, filled from the start.
struct Chunk {
    ptr: *mut u8,
    len: usize,
    used: usize,
    kind: Kind,
    finalized: bool,
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Code,
    ReadOnly,
    Writable,
}

/// A `JITMemoryProvider` whose mappings lie near the executable's code.
#[derive(Default)]
pub struct NearMemory {
    chunks: Vec<Chunk>,
}

// SAFETY: the chunks are private mappings owned by this provider alone; moving it to another
// thread moves that ownership.
unsafe impl Send for NearMemory {}

impl NearMemory {
    /// A provider with nothing mapped yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Maps `len` read-write bytes, near this code when possible.
    fn map(len: usize) -> io::Result<*mut u8> {
        let anchor = Self::map as *const () as usize;
        let page = page_size();
        let base = anchor & !(page - 1);
        for i in 1..=(REACH / STEP) {
            let Some(hint) = base.checked_sub(i * STEP) else {
                break;
            };
            let p = mmap(hint, len)?;
            if p.abs_diff(anchor) + len <= REACH {
                return Ok(p as *mut u8);
            }
            unmap(p, len);
        }
        mmap(0, len).map(|p| p as *mut u8)
    }
}

impl JITMemoryProvider for NearMemory {
    fn allocate(&mut self, size: usize, align: u64, kind: JITMemoryKind) -> io::Result<*mut u8> {
        let kind = match kind {
            JITMemoryKind::Executable => Kind::Code,
            JITMemoryKind::ReadOnly => Kind::ReadOnly,
            JITMemoryKind::Writable => Kind::Writable,
        };
        let align = usize::try_from(align)
            .ok()
            .filter(|a| a.is_power_of_two() && *a <= page_size())
            .ok_or_else(|| io::Error::other("unsupported alignment"))?;
        let fits = |c: &Chunk| {
            c.kind == kind && !c.finalized && c.used.next_multiple_of(align) + size <= c.len
        };
        let index = match self.chunks.iter().position(fits) {
            Some(i) => i,
            None => {
                let len = size.max(CHUNK).next_multiple_of(page_size());
                let ptr = Self::map(len)?;
                self.chunks.push(Chunk {
                    ptr,
                    len,
                    used: 0,
                    kind,
                    finalized: false,
                });
                self.chunks.len() - 1
            }
        };
        let chunk = &mut self.chunks[index];
        let at = chunk.used.next_multiple_of(align);
        chunk.used = at + size;
        // SAFETY: `at + size <= len` (checked by `fits`, or a fresh chunk of at least
        // `size` bytes), so the pointer stays inside the mapping.
        Ok(unsafe { chunk.ptr.add(at) })
    }

    /// Unmaps every chunk.
    ///
    /// # Safety
    /// No pointer into the pages (code or data) may be used afterwards: the contract of
    /// `JITModule::free_memory`, which calls this (as do `Drop` and the test).
    unsafe fn free_memory(&mut self) {
        for c in self.chunks.drain(..) {
            unmap(c.ptr as usize, c.len);
        }
    }

    fn finalize(&mut self, _: BranchProtection) -> ModuleResult<()> {
        for c in self.chunks.iter_mut().filter(|c| !c.finalized) {
            let prot = match c.kind {
                Kind::Code => libc::PROT_READ | libc::PROT_EXEC,
                Kind::ReadOnly => libc::PROT_READ,
                Kind::Writable => libc::PROT_READ | libc::PROT_WRITE,
            };
            // SAFETY: `ptr..ptr + len` is a mapping this provider made and still owns.
            if unsafe { libc::mprotect(c.ptr.cast(), c.len, prot) } != 0 {
                return Err(ModuleError::Backend(io::Error::last_os_error().into()));
            }
            c.finalized = true;
        }
        Ok(())
    }
}

impl Drop for NearMemory {
    fn drop(&mut self) {
        // The module frees its memory explicitly (`Code`'s drop); this covers a module
        // dropped before finalisation, whose pages nothing can point into.
        if self.chunks.iter().all(|c| !c.finalized) {
            // SAFETY: nothing was finalised, so no code pointer into these pages exists.
            unsafe { self.free_memory() };
        }
    }
}

fn page_size() -> usize {
    // SAFETY: sysconf has no preconditions.
    let size = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    usize::try_from(size).unwrap_or(4096)
}

/// An anonymous private read-write mapping of `len` bytes, at `hint` if that is free
/// (0: anywhere).
fn mmap(hint: usize, len: usize) -> io::Result<usize> {
    // SAFETY: an anonymous mapping without MAP_FIXED never replaces an existing one; the
    // hint is only a hint.
    let p = unsafe {
        libc::mmap(
            hint as *mut libc::c_void,
            len,
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if p == libc::MAP_FAILED {
        Err(io::Error::last_os_error())
    } else {
        Ok(p as usize)
    }
}

fn unmap(p: usize, len: usize) {
    // SAFETY: callers pass a whole mapping made by `mmap` that nothing points into.
    unsafe { libc::munmap(p as *mut libc::c_void, len) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mappings_land_near_the_code_and_take_each_kind_apart() {
        let mut m = NearMemory::new();
        let code = m.allocate(100, 16, JITMemoryKind::Executable).unwrap();
        let data = m.allocate(8, 8, JITMemoryKind::ReadOnly).unwrap();
        let more = m.allocate(100, 16, JITMemoryKind::Executable).unwrap();
        let anchor = NearMemory::map as *const () as usize;
        assert!(
            (code as usize).abs_diff(anchor) < REACH,
            "{code:p} vs {anchor:#x}"
        );
        assert_eq!(more as usize, code as usize + 112);
        assert_eq!(m.chunks.len(), 2);
        assert_eq!(data as usize % 8, 0);
        // SAFETY: `allocate` gave 100 bytes at `code` inside a mapping it made read-write,
        // and nothing has finalised (write-protected) it yet.
        unsafe { code.write_bytes(0xc3, 100) };
        m.finalize(BranchProtection::None).unwrap();
        // After finalisation new requests get new pages.
        let after = m.allocate(8, 8, JITMemoryKind::Executable).unwrap();
        assert_eq!(m.chunks.len(), 3);
        assert!(after as usize != more as usize + 100);
        // SAFETY: `code`, `data`, `more` and `after` are not used after this.
        unsafe { m.free_memory() };
        assert!(m.chunks.is_empty());
    }
}
