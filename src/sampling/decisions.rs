//! How a render takes its sampling decisions (docs/guarantees.md,
//! Sampling decisions): its own, or another render's replayed
//! ([`Decider`]), and what it decided ([`Sampled`]). The decisions
//! themselves, which a scene may carry to replay, are
//! `scene::decisions::Decisions`.

use crate::scene::decisions::{Decisions, Kind};

/// What a render's sampling decided.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Sampled {
    /// The decisions that went the way of more samples (a square split, a
    /// pixel went on): its own, or those it replayed.
    pub taken: Decisions,
    /// Where it replayed another's: the decisions it would have taken
    /// otherwise on the same samples. Empty where it took its own.
    pub otherwise: Decisions,
    /// How many decisions it took.
    pub count: usize,
}

/// How a render takes its decisions: its own, or another render's
/// replayed (`Scene::replay`).
#[derive(Debug, Clone, Copy)]
pub struct Decider<'a> {
    /// The decisions to replay, where there are.
    pub replay: Option<&'a Decisions>,
}

impl Decider<'_> {
    /// The decision at `key`, where the render's own test says `own`:
    /// `own`, or the replayed one; written into `log`.
    pub fn decide(&self, key: u64, own: bool, log: &mut Log) -> bool {
        let taken = self.replay.map_or(own, |r| r.holds(key));
        log.count += 1;
        if taken {
            log.taken.push(key);
        }
        if taken != own {
            log.otherwise.push(key);
        }
        taken
    }
}

/// A part of a render's decisions, as they are taken.
#[derive(Debug, Default)]
pub struct Log {
    taken: Vec<u64>,
    otherwise: Vec<u64>,
    count: usize,
}

impl Log {
    /// Both parts' decisions.
    pub fn merge(mut self, other: Log) -> Log {
        self.taken.extend(other.taken);
        self.otherwise.extend(other.otherwise);
        self.count += other.count;
        self
    }

    /// The decisions of sampling `kind`, sorted.
    pub fn sampled(self, kind: Kind) -> Sampled {
        Sampled {
            taken: Decisions::new(kind, self.taken),
            otherwise: Decisions::new(kind, self.otherwise),
            count: self.count,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::decisions::key;

    /// A replaying decider takes the replayed decision and notes where its
    /// own test said otherwise; its own decider takes its own.
    #[test]
    fn a_replay_takes_the_replayed_decision_and_notes_its_own() {
        let replayed = Decisions::new(Kind::Contrast, vec![key(0, 1, 1)]);
        let mut log = Log::default();
        let replay = Decider {
            replay: Some(&replayed),
        };
        assert!(replay.decide(key(0, 1, 1), false, &mut log));
        assert!(!replay.decide(key(0, 2, 1), false, &mut log));
        assert!(!replay.decide(key(0, 3, 1), true, &mut log));
        let own = Decider { replay: None };
        assert!(own.decide(key(0, 4, 1), true, &mut log));
        let s = log.sampled(Kind::Contrast);
        assert_eq!(s.taken.keys(), &[key(0, 1, 1), key(0, 4, 1)]);
        assert_eq!(s.otherwise.keys(), &[key(0, 1, 1), key(0, 3, 1)]);
        assert_eq!(s.count, 4);
    }
}
