//! Each generated kernel's WGSL in naga's IR, costed on its worst path and with
//! every branch taken.

use crate::kernel::KernelSpec;
use crate::output::Output;

/// A general model's kernel as its WGSL `airlight` function counts in naga's IR
/// ([`airlight_shapes::ircost`]): on its worst path and with every branch taken.
#[derive(Debug, Clone, PartialEq)]
pub struct KernelIr {
    /// The model's name.
    pub name: String,
    /// Operations on the worst path.
    pub worst: airlight_shapes::ircost::IrCost,
    /// Operations with every branch taken.
    pub every: airlight_shapes::ircost::IrCost,
}

/// Every general model's [`KernelIr`], from the WGSL the generator rendered
/// (`wgsl/<name>.wgsl` among `kernels`).
pub fn kernel_ir(specs: &[KernelSpec], kernels: &[Output]) -> Result<Vec<KernelIr>, tera::Error> {
    specs
        .iter()
        .filter(|s| s.scene.is_none())
        .filter_map(|s| {
            let path = format!("wgsl/{}.wgsl", s.name);
            let src = kernels.iter().find(|o| o.path == path)?;
            Some((s, path, String::from_utf8_lossy(&src.contents).into_owned()))
        })
        .map(|(s, path, src)| {
            let f = format!("{}airlight", s.prefix());
            let fail = |e: String| tera::Error::msg(format!("{path}: {e}"));
            let (worst, every) = airlight_shapes::ircost::ir_costs(&src, &f).map_err(fail)?;
            Ok(KernelIr { name: s.name.clone(), worst, every })
        })
        .collect()
}
