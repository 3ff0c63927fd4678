//! The frame's graph, small and fixed: every pass declares the targets it creates, reads and
//! writes ([`Access`], one constant per pass beside its code), and from those declarations
//! alone come where each pass records ([`Stage`]), the order the frame records them in
//! ([`order`]) and the transient targets a renderer makes for the frame's size
//! ([`transient`]). Nothing here names a pass.

/// A target (a texture or a set of them) the frame's passes share.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The key light's depth map (made at load where something casts).
    ShadowMap,
    /// The distance to the nearest shadow edge, over a grid of the shadow map.
    PenumbraMap,
    /// The scene's colour and depth: the output's MSAA target, or, in a frame whose pass
    /// reads [`Target::Split`], the split targets.
    Scene,
    /// The scene in linear radiance split in three (`targets::SplitTargets`): made for the
    /// frame's size (transient), where a built pass creates it.
    Split,
    /// The image presented: the frame's last pass resolves into it.
    Output,
}

impl Target {
    /// Whether it is made for the frame's size by `Renderer::resize` (else at load).
    pub const fn transient(self) -> bool {
        matches!(self, Target::Split)
    }

    /// Whether it is one of the light's maps (drawn in passes of their own, before the
    /// scene).
    pub const fn light(self) -> bool {
        matches!(self, Target::ShadowMap | Target::PenumbraMap)
    }
}

/// What one pass does with the frame's targets.
#[derive(Clone, Copy, Debug)]
pub struct Access {
    /// Targets it needs made (transient ones at the frame's size).
    pub creates: &'static [Target],
    /// Targets it samples: their writers run first.
    pub reads: &'static [Target],
    /// Targets it draws into.
    pub writes: &'static [Target],
}

/// Where a pass records, from what it writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    /// Before the scene, in passes of its own (it writes only light maps).
    Light,
    /// Inside the scene's pass (it writes [`Target::Scene`]).
    Scene,
    /// Inside the frame's last pass, which resolves into the output (it writes
    /// [`Target::Output`]; in a frame of one pass, the scene's, after the scene's draws).
    Last,
}

fn has(list: &[Target], t: Target) -> bool {
    list.contains(&t)
}

impl Access {
    /// Where it records: the last pass if it writes the output, the scene's if it writes
    /// the scene, else a pass of its own (light maps).
    pub fn stage(&self) -> Stage {
        if has(self.writes, Target::Output) {
            Stage::Last
        } else if has(self.writes, Target::Scene) {
            Stage::Scene
        } else {
            Stage::Light
        }
    }

    /// Whether this pass must record after `other`: it reads what `other` writes, or `other`
    /// records in an earlier stage. (The scene is read by the passes that read its split
    /// targets: they follow every pass that draws the scene.)
    pub fn after(&self, other: &Access) -> bool {
        let reads = |t: &Target| {
            has(self.reads, *t) || (*t == Target::Scene && has(self.reads, Target::Split))
        };
        other.writes.iter().any(reads) || other.stage() < self.stage()
    }
}

/// The order the frame records `passes` (declared in table order) in: each pass after those
/// it must follow ([`Access::after`]), otherwise in table order; `None` where the
/// declarations contradict each other (a cycle).
pub fn order<const N: usize>(passes: &[Access; N]) -> Option<[usize; N]> {
    let mut out = [0; N];
    let mut placed = [false; N];
    for slot in out.iter_mut() {
        let next = (0..N).find(|&i| {
            !placed[i] && (0..N).all(|j| j == i || placed[j] || !passes[i].after(&passes[j]))
        })?;
        placed[next] = true;
        *slot = next;
    }
    Some(out)
}

/// The transient targets the passes built (`built`, table order) create.
pub fn transient<const N: usize>(
    passes: &[Access; N],
    built: [bool; N],
) -> impl Iterator<Item = Target> + '_ {
    passes
        .iter()
        .zip(built)
        .filter(|(_, b)| *b)
        .flat_map(|(a, _)| a.creates.iter().copied())
        .filter(|t| t.transient())
}

/// Why `passes` in `order` is not a valid frame: a target read before (or without) its
/// writer, a stage out of order, a transient target nobody creates, a pass that writes
/// nothing.
pub fn check<const N: usize>(passes: &[Access; N], order: &[usize; N]) -> Result<(), String> {
    let mut seen = [false; N];
    for &i in order {
        seen[i] = true;
    }
    if seen.iter().any(|s| !s) {
        return Err("the order does not hold every pass once".into());
    }
    for (k, &i) in order.iter().enumerate() {
        let a = &passes[i];
        if a.writes.is_empty() {
            return Err(format!("pass {i} writes nothing"));
        }
        for &j in &order[k + 1..] {
            if a.after(&passes[j]) {
                return Err(format!(
                    "pass {i} records before pass {j}, which it must follow"
                ));
            }
        }
        for t in a.reads {
            let written = passes
                .iter()
                .any(|p| has(p.writes, *t) || has(p.creates, *t));
            if !written {
                return Err(format!(
                    "pass {i} reads {t:?}, which no pass writes or creates"
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIGHT: Access = Access {
        creates: &[],
        reads: &[],
        writes: &[Target::ShadowMap],
    };
    const SCENE: Access = Access {
        creates: &[],
        reads: &[Target::ShadowMap],
        writes: &[Target::Scene],
    };
    const GATHER: Access = Access {
        creates: &[Target::Split],
        reads: &[Target::Split],
        writes: &[Target::Output],
    };

    #[test]
    fn order_follows_the_declarations_not_the_table() {
        // Listed backwards, ordered forwards.
        let passes = [GATHER, SCENE, LIGHT];
        let order = order(&passes).expect("no cycle");
        assert_eq!(order, [2, 1, 0]);
        assert!(check(&passes, &order).is_ok());
        // The table's order, where nothing else decides.
        let two = [SCENE, SCENE];
        assert_eq!(super::order(&two), Some([0, 1]));
        // A wrong order is caught.
        assert!(check(&passes, &[0, 1, 2]).is_err());
        assert_eq!(LIGHT.stage(), Stage::Light);
        assert_eq!(SCENE.stage(), Stage::Scene);
        assert_eq!(GATHER.stage(), Stage::Last);
    }

    #[test]
    fn a_cycle_has_no_order_and_transients_come_from_built_creators() {
        let a = Access {
            creates: &[],
            reads: &[Target::PenumbraMap],
            writes: &[Target::ShadowMap],
        };
        let b = Access {
            creates: &[],
            reads: &[Target::ShadowMap],
            writes: &[Target::PenumbraMap],
        };
        assert_eq!(order(&[a, b]), None);
        let passes = [LIGHT, GATHER];
        let made: Vec<_> = transient(&passes, [true, true]).collect();
        assert_eq!(made, [Target::Split]);
        assert_eq!(transient(&passes, [true, false]).count(), 0);
    }
}
