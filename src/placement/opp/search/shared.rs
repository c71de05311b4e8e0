//! The dead profiles of one box, shared by every search that works on it: its threads, and the
//! pilot and the rest of a contact enumeration.
//!
//! Why sharing keeps every answer: a profile is recorded only for a state whose subtree held no
//! complete x-assignment without any contact cut (`Search::record_dead`), and whether a state
//! has one depends only on the state (its placed set, position and open objects), not on the
//! path, the thread, the task or the contact bound. So a profile recorded by one search cuts
//! only subtrees without a packing in any other search of the same box. Each search used to
//! keep its own, and two threads visited 20–35 % more nodes of a twenty-object contact
//! enumeration than one; without the memo, one and two visit the same nodes.

use super::*;
use std::sync::RwLock;

/// The profiles and the arena holding them (as `Search::dominant[0]` and `Search::arena`).
#[derive(Default)]
struct Table {
    lists: Profiles,
    arena: Vec<(i32, i32)>,
    /// Profiles kept, counted against [`DEAD_MAX`].
    len: usize,
}

/// Dead profiles by (placed set, position), shared between searches of one box and one set of
/// items: lookups read, records write, each in one of [`SHARDS`] tables chosen by the key (one
/// lock for all made two threads slower than before on n20_k4_s0011 and s0017: 0.054 → 0.075 s
/// and 0.258 → 0.274 s, with fewer nodes).
pub(in crate::placement::opp) struct SharedProfiles {
    tables: Vec<RwLock<Table>>,
}

/// Tables of [`SharedProfiles`], each with its share of the memo's size.
const SHARDS: usize = 64;

impl Default for SharedProfiles {
    fn default() -> Self {
        SharedProfiles {
            tables: (0..SHARDS).map(|_| RwLock::default()).collect(),
        }
    }
}

impl SharedProfiles {
    /// The table of key `at`.
    fn table(&self, at: (u64, i32)) -> &RwLock<Table> {
        let mut h = FxHasher::default();
        h.write_u64(at.0);
        h.write_i64(at.1 as i64);
        &self.tables[(h.finish() >> 58) as usize % SHARDS]
    }

    /// Whether a profile recorded at `at` (placed set, position) cuts `profile` — one with no
    /// more load anywhere ahead (`dominance`), or the same one without it — and whether one is
    /// the same.
    pub(super) fn lookup(&self, at: (u64, i32), profile: &[(i32, i32)], dominance: bool) -> (bool, bool) {
        let table = self.table(at).read().expect("no search panics holding the profiles");
        let Some(list) = table.lists.get(&at) else {
            return (false, false);
        };
        let of = |&p: &Profile| in_arena(&table.arena, p);
        let same = list.iter().any(|p| of(p) == profile);
        let cut = same || (dominance && list.iter().any(|p| dominated(profile, of(p))));
        (cut, same)
    }

    /// Record `profile` at `at` as dead: those it dominates go (`dominance`). The table starts
    /// afresh when full, as each search's own did.
    pub(super) fn record(&self, at: (u64, i32), profile: &[(i32, i32)], dominance: bool, cap: usize) {
        let mut table = self.table(at).write().expect("no search panics holding the profiles");
        let table = &mut *table;
        if table.len >= cap.div_ceil(SHARDS) || table.arena.len() + profile.len() > ARENA_MAX / SHARDS {
            table.lists.clear();
            table.len = 0;
            table.arena.clear();
        }
        let p: Profile = (table.arena.len() as u32, profile.len() as u32);
        table.arena.extend_from_slice(profile);
        let list = table.lists.entry(at).or_default();
        let before = list.len();
        if dominance {
            let arena = &table.arena;
            list.retain(|&q| !dominated(in_arena(arena, q), profile));
        }
        table.len = table.len + 1 + list.len() - before;
        list.push(p);
    }
}
