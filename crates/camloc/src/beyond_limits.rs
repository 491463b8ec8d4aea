//! Poses whose joints the reconstruction bent far past the motion capture's joint limits
//! ([`LimitCount`]): most of a run's, when its landmarks are not in the order of the layout
//! they were read as.

/// How far past the joint limits (radians, a reconstruction's `outside_limits_rad`) a pose
/// counts as beyond them for [`LimitCount`].
pub const BEYOND_LIMITS_RAD: f64 = 0.1;

/// The share of a run's poses beyond the limits from which [`LimitCount::summary`] speaks: a
/// simulated animator's 14-joint array in another joint order, read as LSP-14, had 76 of its
/// 90 frames past them (84%; 87 with `--sequence`) and nothing said; LSP's 392 sports photos
/// have 28%, that user's 2,480 frames of CMU clips filmed by four cameras 1.8%. Gross
/// reorderings only: a reviewer's left and right sides or x and y swapped were not caught.
pub const BEYOND_LIMITS_SHARE: f64 = 0.6;

/// The fewest poses a [`LimitCount`] speaks of.
pub const BEYOND_LIMITS_MIN_POSES: u64 = 10;

/// The poses of a run and, of those, the ones reconstructed more than [`BEYOND_LIMITS_RAD`]
/// past the joint limits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LimitCount {
    /// Poses counted.
    pub poses: u64,
    /// Of those, the poses beyond the limits.
    pub beyond: u64,
}

impl LimitCount {
    /// Counts a pose reconstructed `outside_limits_rad` past the joint limits.
    pub fn add(&mut self, outside_limits_rad: f64) {
        self.poses += 1;
        self.beyond += u64::from(!(outside_limits_rad <= BEYOND_LIMITS_RAD));
    }

    /// `None` unless at least [`BEYOND_LIMITS_MIN_POSES`] poses were counted and more than
    /// [`BEYOND_LIMITS_SHARE`] of them are beyond the limits; else e.g. `88 of 90 poses were
    /// reconstructed with joints bent past the limits of motion capture (by more than 0.1 rad):
    /// are the landmarks in the order of the layout they were read as?`.
    pub fn summary(&self) -> Option<String> {
        let share = self.beyond as f64 / self.poses.max(1) as f64;
        (self.poses >= BEYOND_LIMITS_MIN_POSES && share > BEYOND_LIMITS_SHARE).then(|| {
            format!(
                "{} of {} poses were reconstructed with joints bent past the limits of motion \
                 capture (by more than {BEYOND_LIMITS_RAD} rad): are the landmarks in the order \
                 of the layout they were read as?",
                self.beyond, self.poses
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn most_poses_past_the_limits_are_said_few_are_not() {
        let mut count = LimitCount::default();
        for m in 0..10 {
            count.add(if m < 7 { 0.38 } else { 0.0 });
        }
        let said = count.summary().unwrap();
        assert!(said.starts_with("7 of 10 poses"), "{said}");
        let mut sports = LimitCount::default();
        for m in 0..100 {
            sports.add(if m < 60 { 0.5 } else { 0.01 });
        }
        assert_eq!(sports.summary(), None);
        let mut few = LimitCount::default();
        (0..9).for_each(|_| few.add(1.0));
        assert_eq!(few.summary(), None);
        let mut nan = LimitCount::default();
        (0..10).for_each(|_| nan.add(f64::NAN));
        assert!(nan.summary().is_some());
    }
}
