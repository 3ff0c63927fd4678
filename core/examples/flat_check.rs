use dermis_core::probe::Probe;
use dermis_core::reference::{self, metric, ReferenceSet};
use dermis_core::render::Gpu;
use dermis_core::shading::ShadingModel;

fn main() {
    let gpu = Gpu::headless().unwrap();
    let mut probe = Probe::new(&gpu);
    let only: Option<String> = std::env::args().nth(1);
    for m in reference::acceptance_materials() {
        let set =
            ReferenceSet::load(&reference::file_for(&reference::default_dir(), m.name)).unwrap();
        for e in &set.entries {
            if let Some(o) = &only {
                if !e.scene.label().contains(o.as_str()) {
                    continue;
                }
            }
            let mut line = format!("{:11} {:22}", m.name, e.scene.label());
            for model in [
                ShadingModel::Burley,
                ShadingModel::Tabulated,
                ShadingModel::Preintegrated,
                ShadingModel::Ward,
                ShadingModel::OssStable,
            ] {
                match probe.render(&gpu, model, &m, &e.scene, &e.edges) {
                    Ok(r) => {
                        let s = metric::score(&r, e);
                        line += &format!(
                            " {}={:.3}/{:.3}",
                            &model.name()[..3],
                            s.mean_log_all,
                            s.integrated_all
                        );
                        if std::env::var("DUMP")
                            .map(|v| v == model.name())
                            .unwrap_or(false)
                        {
                            for k in 0..r.len() {
                                println!(
                                    "   {:.2}-{:.2} model {:.3e} ref {:.3e} se {:.1e} ratio {:.3}",
                                    e.edges[k],
                                    e.edges[k + 1],
                                    r[k][0],
                                    e.values[k][0],
                                    e.std_err[k][0],
                                    r[k][0] / e.values[k][0]
                                );
                            }
                        }
                    }
                    Err(err) => line += &format!(" {}=ERR({err})", model.name()),
                }
            }
            println!(
                "{line}  (ref se {:.3})",
                metric::score(&e.values, e).ref_rel_se_all
            );
        }
    }
}
