//! Fixed-capacity object pools with generation-checked handles (§4.3: no per-frame object
//! creation). A pool allocates its slots once, at construction; `insert` never grows it (it
//! returns `None` when full) and a handle to a removed item is rejected even after its slot
//! has been reused.

/// A reference to a pool item: the slot index and the slot's generation when it was filled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Handle {
    pub index: u32,
    pub generation: u32,
}

struct Slot<T> {
    /// Bumped every time the slot is emptied, so older handles no longer match.
    generation: u32,
    value: Option<T>,
}

/// A fixed-capacity pool.
pub struct Pool<T> {
    slots: Vec<Slot<T>>,
    /// Free slot indices, used as a stack (lowest index on top after construction).
    free: Vec<u32>,
    len: usize,
}

impl<T> Pool<T> {
    /// A pool of `capacity` empty slots (the only allocation it ever makes).
    pub fn with_capacity(capacity: usize) -> Self {
        assert!(capacity <= u32::MAX as usize, "pool capacity exceeds u32");
        let mut slots = Vec::with_capacity(capacity);
        slots.extend((0..capacity).map(|_| Slot {
            generation: 0,
            value: None,
        }));
        Self {
            slots,
            free: (0..capacity as u32).rev().collect(),
            len: 0,
        }
    }

    pub fn capacity(&self) -> usize {
        self.slots.len()
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn is_full(&self) -> bool {
        self.free.is_empty()
    }

    /// Stores `value`; `None` when the pool is full (it never grows).
    pub fn insert(&mut self, value: T) -> Option<Handle> {
        let index = self.free.pop()?;
        let slot = &mut self.slots[index as usize];
        debug_assert!(slot.value.is_none());
        slot.value = Some(value);
        self.len += 1;
        Some(Handle {
            index,
            generation: slot.generation,
        })
    }

    fn slot(&self, h: Handle) -> Option<&Slot<T>> {
        self.slots
            .get(h.index as usize)
            .filter(|s| s.generation == h.generation)
    }

    pub fn contains(&self, h: Handle) -> bool {
        self.slot(h).is_some_and(|s| s.value.is_some())
    }

    /// The item, or `None` for a stale or foreign handle.
    pub fn get(&self, h: Handle) -> Option<&T> {
        self.slot(h)?.value.as_ref()
    }

    pub fn get_mut(&mut self, h: Handle) -> Option<&mut T> {
        let slot = self.slots.get_mut(h.index as usize)?;
        if slot.generation != h.generation {
            return None;
        }
        slot.value.as_mut()
    }

    /// Removes and returns the item; `None` (and no change) for a stale handle.
    pub fn remove(&mut self, h: Handle) -> Option<T> {
        let slot = self.slots.get_mut(h.index as usize)?;
        if slot.generation != h.generation {
            return None;
        }
        let value = slot.value.take()?;
        slot.generation = slot.generation.wrapping_add(1);
        self.free.push(h.index);
        self.len -= 1;
        Some(value)
    }

    /// Removes every item for which `keep` returns false.
    pub fn retain(&mut self, mut keep: impl FnMut(Handle, &mut T) -> bool) {
        for index in 0..self.slots.len() {
            let slot = &mut self.slots[index];
            let generation = slot.generation;
            let Some(value) = slot.value.as_mut() else {
                continue;
            };
            if !keep(
                Handle {
                    index: index as u32,
                    generation,
                },
                value,
            ) {
                self.remove(Handle {
                    index: index as u32,
                    generation,
                });
            }
        }
    }

    /// Removes every item (handles to them become stale).
    pub fn clear(&mut self) {
        self.retain(|_, _| false);
    }

    /// Live items in slot order (deterministic).
    pub fn iter(&self) -> impl Iterator<Item = (Handle, &T)> + '_ {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            s.value.as_ref().map(|v| {
                (
                    Handle {
                        index: i as u32,
                        generation: s.generation,
                    },
                    v,
                )
            })
        })
    }

    pub fn iter_mut(&mut self) -> impl Iterator<Item = (Handle, &mut T)> + '_ {
        self.slots.iter_mut().enumerate().filter_map(|(i, s)| {
            let generation = s.generation;
            s.value.as_mut().map(|v| {
                (
                    Handle {
                        index: i as u32,
                        generation,
                    },
                    v,
                )
            })
        })
    }

    /// Live items only (slot order).
    pub fn values(&self) -> impl Iterator<Item = &T> + '_ {
        self.slots.iter().filter_map(|s| s.value.as_ref())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capacity_is_fixed() {
        let mut p = Pool::with_capacity(3);
        let a = p.insert(1).unwrap();
        p.insert(2).unwrap();
        p.insert(3).unwrap();
        assert!(p.is_full());
        assert_eq!(p.insert(4), None);
        assert_eq!(p.len(), 3);
        assert_eq!(p.capacity(), 3);
        p.remove(a);
        assert!(p.insert(5).is_some());
        assert_eq!(p.insert(6), None);
    }

    #[test]
    fn slots_are_reused_and_stale_handles_rejected() {
        let mut p = Pool::with_capacity(2);
        let a = p.insert("a").unwrap();
        assert_eq!(p.remove(a), Some("a"));
        let b = p.insert("b").unwrap();
        assert_eq!(a.index, b.index, "slot reused");
        assert_ne!(a.generation, b.generation);
        assert_eq!(p.get(a), None);
        assert_eq!(p.get_mut(a), None);
        assert_eq!(p.remove(a), None);
        assert!(!p.contains(a));
        assert_eq!(p.get(b), Some(&"b"));
        assert_eq!(p.len(), 1);
        // Out-of-range handles too.
        assert_eq!(
            p.get(Handle {
                index: 99,
                generation: 0
            }),
            None
        );
    }

    #[test]
    fn iteration_retain_clear() {
        let mut p = Pool::with_capacity(8);
        let hs: Vec<Handle> = (0..6).map(|i| p.insert(i).unwrap()).collect();
        p.remove(hs[1]);
        assert_eq!(p.values().copied().collect::<Vec<_>>(), vec![0, 2, 3, 4, 5]);
        p.retain(|_, v| *v % 2 == 0);
        assert_eq!(p.values().copied().collect::<Vec<_>>(), vec![0, 2, 4]);
        for (_, v) in p.iter_mut() {
            *v *= 10;
        }
        assert_eq!(
            p.iter().map(|(_, v)| *v).collect::<Vec<_>>(),
            vec![0, 20, 40]
        );
        p.clear();
        assert!(p.is_empty());
        assert!(hs.iter().all(|h| p.get(*h).is_none()));
        assert_eq!(p.free.len(), 8);
    }

    #[test]
    fn no_allocation_after_construction() {
        let mut p: Pool<[u8; 16]> = Pool::with_capacity(4);
        let (sc, fc) = (p.slots.capacity(), p.free.capacity());
        for _ in 0..100 {
            let hs: Vec<Handle> = (0..4).map(|_| p.insert([0; 16]).unwrap()).collect();
            for h in hs {
                p.remove(h);
            }
        }
        assert_eq!((p.slots.capacity(), p.free.capacity()), (sc, fc));
    }
}
