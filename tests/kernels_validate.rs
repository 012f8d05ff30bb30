//! Every WGSL file in `kernels/` is registered, valid for naga, and agrees with its registry entry
//! (entry point, workgroup size, bindings, CPU twin) and with the Rust structs it mirrors.
//! Needs no GPU.

use std::path::{Path, PathBuf};

use naga::valid::{Capabilities, ValidationFlags, Validator};
use surftrack::compute::Access;
use surftrack::kernels::{GPU_STRUCTS, KERNELS, SHARED};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Every `.wgsl` file under `kernels/`, as paths relative to the crate root, sorted.
fn wgsl_files_on_disk() -> Vec<String> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(&root().join("kernels"), &mut files);
    let mut relative: Vec<String> = files
        .iter()
        .map(|p| {
            p.strip_prefix(root())
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/")
        })
        .collect();
    relative.sort();
    relative
}

/// Parses and validates `source` with every validation flag, naming `path` on failure. The fine
/// stage's kernels compute in f64, which the device opens where the adapter has it.
fn validate(path: &str, source: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| {
        format!(
            "{path}: WGSL parse error\n{}",
            e.emit_to_string_with_path(source, path)
        )
    })?;
    Validator::new(
        ValidationFlags::all(),
        Capabilities::default() | Capabilities::FLOAT64,
    )
    .validate(&module)
    .map_err(|e| {
        format!(
            "{path}: naga validation error\n{}",
            e.emit_to_string_with_path(source, path)
        )
    })?;
    Ok(module)
}

#[test]
fn every_kernel_file_is_registered_and_every_entry_exists() {
    let on_disk = wgsl_files_on_disk();
    assert!(!on_disk.is_empty(), "no .wgsl files found under kernels/");
    let registered: Vec<&str> = KERNELS
        .iter()
        .map(|k| k.path)
        .chain(SHARED.iter().map(|s| s.path))
        .collect();
    let unregistered: Vec<&String> = on_disk
        .iter()
        .filter(|f| !registered.contains(&f.as_str()))
        .collect();
    assert!(
        unregistered.is_empty(),
        "kernel files missing from src/kernels/mod.rs: {unregistered:?}"
    );
    let missing: Vec<&&str> = registered
        .iter()
        .filter(|p| !on_disk.iter().any(|f| f == **p))
        .collect();
    assert!(
        missing.is_empty(),
        "registered but not on disk: {missing:?}"
    );

    let mut names: Vec<&str> = KERNELS.iter().map(|k| k.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), KERNELS.len(), "duplicate kernel names");
    for kernel in KERNELS {
        assert_eq!(
            kernel.path,
            format!("kernels/{}.wgsl", kernel.name),
            "kernel {:?} must live in a file named after it",
            kernel.name
        );
        for shared in kernel.shared {
            assert!(
                SHARED.contains(shared),
                "{}: {} is not in SHARED",
                kernel.path,
                shared.path
            );
        }
    }
}

#[test]
fn every_wgsl_file_validates() {
    let mut failures = Vec::new();
    for path in wgsl_files_on_disk() {
        let own = std::fs::read_to_string(root().join(&path)).unwrap();
        // A kernel is compiled with its shared declarations prepended; validate what the GPU sees.
        let source = KERNELS
            .iter()
            .find(|k| k.path == path)
            .map_or(own, |k| k.full_source());
        if let Err(message) = validate(&path, &source) {
            failures.push(message);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn registry_entries_match_their_shaders() {
    for kernel in KERNELS {
        let module = validate(kernel.path, &kernel.full_source()).unwrap();
        let entry = module
            .entry_points
            .iter()
            .find(|e| e.name == kernel.entry_point)
            .unwrap_or_else(|| panic!("{}: no entry point {:?}", kernel.path, kernel.entry_point));
        assert_eq!(entry.stage, naga::ShaderStage::Compute, "{}", kernel.path);
        assert_eq!(
            entry.workgroup_size,
            [kernel.workgroup_size, 1, 1],
            "{}: @workgroup_size differs from the registry",
            kernel.path
        );

        let mut bound: Vec<(u32, u32, String, naga::AddressSpace)> = module
            .global_variables
            .iter()
            .filter_map(|(_, var)| {
                let binding = var.binding.as_ref()?;
                Some((
                    binding.group,
                    binding.binding,
                    var.name.clone().unwrap_or_default(),
                    var.space,
                ))
            })
            .collect();
        bound.sort_by_key(|b| (b.0, b.1));
        let expected: Vec<(u32, u32, String, naga::AddressSpace)> = kernel
            .bindings
            .iter()
            .enumerate()
            .map(|(i, b)| {
                let access = match b.access {
                    Access::Read => naga::StorageAccess::LOAD,
                    Access::ReadWrite => naga::StorageAccess::LOAD | naga::StorageAccess::STORE,
                };
                (
                    0,
                    i as u32,
                    b.name.to_owned(),
                    naga::AddressSpace::Storage { access },
                )
            })
            .collect();
        assert_eq!(
            bound, expected,
            "{}: bindings differ from the registry",
            kernel.path
        );
    }
}

#[test]
fn every_kernel_has_a_cpu_twin_that_names_it() {
    for kernel in KERNELS {
        let twin = root().join(kernel.cpu_twin);
        let text = std::fs::read_to_string(&twin).unwrap_or_else(|e| {
            panic!(
                "{}: CPU twin {} unreadable: {e}",
                kernel.path, kernel.cpu_twin
            )
        });
        assert!(
            text.contains(kernel.path),
            "{}: its CPU twin {} does not mention the kernel file",
            kernel.path,
            kernel.cpu_twin
        );
        let kernel_text = std::fs::read_to_string(root().join(kernel.path)).unwrap();
        assert!(
            kernel_text.contains(kernel.cpu_twin),
            "{}: does not name its CPU twin {}",
            kernel.path,
            kernel.cpu_twin
        );
    }
}

#[test]
fn rust_structs_have_the_layout_naga_computes_for_their_wgsl_mirror() {
    assert!(!GPU_STRUCTS.is_empty());
    for layout in GPU_STRUCTS {
        let path = layout.wgsl.path;
        let module = validate(path, layout.wgsl.source).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, ty) = module
            .types
            .iter()
            .find(|(_, ty)| ty.name.as_deref() == Some(layout.name))
            .unwrap_or_else(|| panic!("{path}: no struct {}", layout.name));
        let naga::TypeInner::Struct { members, span } = &ty.inner else {
            panic!("{path}: {} is not a struct", layout.name);
        };
        let wgsl_members: Vec<(String, usize)> = members
            .iter()
            .map(|m| (m.name.clone().unwrap_or_default(), m.offset as usize))
            .collect();
        let rust_members: Vec<(String, usize)> = layout
            .members
            .iter()
            .map(|&(name, offset)| (name.to_owned(), offset))
            .collect();
        assert_eq!(
            wgsl_members, rust_members,
            "{path}: {} member offsets",
            layout.name
        );
        assert_eq!(*span as usize, layout.size, "{path}: {} size", layout.name);
        assert_eq!(
            layouter[handle].to_stride() as usize,
            layout.size,
            "{path}: {} array stride",
            layout.name
        );
    }
}
