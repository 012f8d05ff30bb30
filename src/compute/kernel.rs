//! What the GPU context needs to know about a kernel: its source, its bindings, its workgroup size.
//! The kernels themselves are listed in `crate::kernels`, above this floor, so the context runs any
//! kernel it is handed without knowing which stages exist.

/// A WGSL file of declarations (structs, constants, functions) that kernels share.
///
/// WGSL has no imports, so a kernel's full source is its shared files concatenated in the order
/// the kernel lists them, followed by the kernel's own file. Shared files must be valid WGSL modules
/// on their own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SharedWgsl {
    /// Path relative to the crate root.
    pub path: &'static str,
    pub source: &'static str,
}

/// How a kernel accesses one of its storage buffers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    Read,
    ReadWrite,
}

/// One storage buffer of a kernel: `@group(0) @binding(i)` where `i` is its position in
/// [`KernelInfo::bindings`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Binding {
    /// The WGSL variable name.
    pub name: &'static str,
    pub access: Access,
}

/// A compute kernel and everything needed to run it and to find its CPU twin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct KernelInfo {
    /// Key of the pipeline cache; also the file stem.
    pub name: &'static str,
    /// Path relative to the crate root.
    pub path: &'static str,
    pub source: &'static str,
    /// Shared declarations prepended to `source`, in order.
    pub shared: &'static [SharedWgsl],
    pub entry_point: &'static str,
    /// Must equal the shader's `@workgroup_size` (x only; kernels are 1-D).
    pub workgroup_size: u32,
    /// Storage buffers of bind group 0, binding `i` at index `i`.
    pub bindings: &'static [Binding],
    /// Path (relative to the crate root) of the Rust function with the same loop shape.
    pub cpu_twin: &'static str,
}

impl KernelInfo {
    /// The source handed to the shader compiler: shared declarations, then the kernel.
    pub fn full_source(&self) -> String {
        let mut full = String::new();
        for shared in self.shared {
            full.push_str(&format!("// ---- {} ----\n", shared.path));
            full.push_str(shared.source);
            full.push('\n');
        }
        full.push_str(&format!("// ---- {} ----\n", self.path));
        full.push_str(self.source);
        full
    }
}

/// The byte layout of a Rust struct that a shared WGSL file mirrors.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpuStructLayout {
    /// The struct's name in both languages.
    pub name: &'static str,
    pub wgsl: &'static SharedWgsl,
    pub size: usize,
    /// Member names (as in WGSL) and byte offsets, in declaration order.
    pub members: &'static [(&'static str, usize)],
}
