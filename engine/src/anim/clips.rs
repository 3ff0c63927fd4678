//! Finding a character's clips by name ([`find_clips`]): the runner's idle, run, jump and
//! death, in whatever file they come from.
//!
//! A clip's name is split into words as material names are ([`name_words`]:
//! `HumanArmature|Female_RunningJump` → human, armature, female, running, jump). For each role,
//! its words ([`Role::words`]) are tried in order: the clips that have the word win, the one
//! with the fewest words first (then the lowest index), so `Female_Jump` beats
//! `Female_RunningJump` for jump and `run` does not take `RunningJump`. When no clip has any of
//! the words, the first word found inside a name (case-insensitive) decides the same way.
//! Explicit names (a clip's name, case-insensitive, or `#N` for its index) override the search.

use crate::asset::skin::name_words;
use crate::asset::Model;

/// What a clip is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Role {
    Idle,
    Run,
    Jump,
    Death,
}

impl Role {
    pub const ALL: [Role; 4] = [Role::Idle, Role::Run, Role::Jump, Role::Death];

    pub fn name(self) -> &'static str {
        match self {
            Role::Idle => "idle",
            Role::Run => "run",
            Role::Jump => "jump",
            Role::Death => "death",
        }
    }

    /// The words that name a clip for this role, best first.
    pub fn words(self) -> &'static [&'static str] {
        match self {
            Role::Idle => &["idle", "stand", "standing", "breathe", "breathing"],
            Role::Run => &["run", "running", "sprint", "jog", "jogging"],
            Role::Jump => &["jump", "jumping", "leap", "hop"],
            Role::Death => &["death", "die", "dying", "dead", "defeat"],
        }
    }
}

/// The clip index found for each role (`None`: not found and not required).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Clips {
    pub idle: Option<usize>,
    pub run: Option<usize>,
    pub jump: Option<usize>,
    pub death: Option<usize>,
}

impl Clips {
    pub fn get(&self, role: Role) -> Option<usize> {
        match role {
            Role::Idle => self.idle,
            Role::Run => self.run,
            Role::Jump => self.jump,
            Role::Death => self.death,
        }
    }

    fn set(&mut self, role: Role, clip: Option<usize>) {
        match role {
            Role::Idle => self.idle = clip,
            Role::Run => self.run = clip,
            Role::Jump => self.jump = clip,
            Role::Death => self.death = clip,
        }
    }
}

/// The clip of `model` whose name suits `role` (see the module docs), if any.
pub fn clip_by_role(model: &Model, role: Role) -> Option<usize> {
    let names: Vec<String> = model
        .animations
        .iter()
        .map(|a| a.name.clone().unwrap_or_default())
        .collect();
    let words: Vec<Vec<String>> = names.iter().map(|n| name_words(n)).collect();
    let best = |hit: &dyn Fn(usize) -> bool, size: &dyn Fn(usize) -> usize| {
        (0..names.len())
            .filter(|&i| hit(i))
            .min_by_key(|&i| (size(i), i))
    };
    for w in role.words() {
        let found = best(&|i| words[i].iter().any(|x| x == w), &|i| words[i].len());
        if found.is_some() {
            return found;
        }
    }
    for w in role.words() {
        let found = best(&|i| names[i].to_lowercase().contains(w), &|i| {
            names[i].len()
        });
        if found.is_some() {
            return found;
        }
    }
    None
}

/// The clips for every role: `overrides` (role, a clip's name or `#index`) first, then by name.
/// A one-line error names the file, what is missing among `required` (or the override that
/// names no clip) and the clips the file has.
pub fn find_clips(
    model: &Model,
    overrides: &[(Role, &str)],
    required: &[Role],
) -> Result<Clips, String> {
    let listed = || {
        let names: Vec<String> = model
            .animations
            .iter()
            .enumerate()
            .map(|(i, a)| match &a.name {
                Some(n) => format!("{n:?}"),
                None => format!("#{i} (unnamed)"),
            })
            .collect();
        if names.is_empty() {
            "it has no clips".to_string()
        } else {
            format!("its clips: {}", names.join(", "))
        }
    };
    let mut clips = Clips::default();
    for role in Role::ALL {
        clips.set(role, clip_by_role(model, role));
    }
    for &(role, name) in overrides {
        let n = model.animations.len();
        let found = match name.strip_prefix('#') {
            Some(k) => k.parse::<usize>().ok().filter(|&i| i < n),
            None => model.animations.iter().position(|a| {
                a.name
                    .as_deref()
                    .is_some_and(|x| x.eq_ignore_ascii_case(name))
            }),
        };
        match found {
            Some(i) => clips.set(role, Some(i)),
            None => {
                return Err(format!(
                    "{}: no clip {name:?} for {} ({})",
                    model.source,
                    role.name(),
                    listed()
                ))
            }
        }
    }
    let missing: Vec<&str> = required
        .iter()
        .filter(|r| clips.get(**r).is_none())
        .map(|r| r.name())
        .collect();
    if !missing.is_empty() {
        let it = if missing.len() == 1 { "it" } else { "them" };
        return Err(format!(
            "{}: no {} clip found by name ({}); name {it} explicitly",
            model.source,
            missing.join(", "),
            listed()
        ));
    }
    Ok(clips)
}
