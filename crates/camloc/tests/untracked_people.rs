//! Of a frame's several poses without person ids (an untracked detector's people), which is
//! the person's ([`camloc::left_out_of_sequence`]).

use camloc::reconstruct::FrameRate;
use camloc::{TorsoAnchor, left_out_of_sequence};

fn at(x: f64, torso: f64) -> Option<TorsoAnchor> {
    Some(TorsoAnchor {
        pelvis: [x, 0.0],
        torso,
    })
}

#[test]
fn of_a_frame_s_poses_the_one_nearest_the_track_is_the_person_s() {
    // A walk, 20 px a frame; frame 3 lists another person (900 px away) first.
    let frames = [0, 0, 1, 2, 3, 3, 4].map(Some);
    let anchors = [
        at(0.0, 100.0),
        at(900.0, 100.0),
        at(20.0, 100.0),
        at(40.0, 100.0),
        at(960.0, 100.0),
        at(60.0, 100.0),
        at(80.0, 100.0),
    ];
    let left = left_out_of_sequence(&frames, &anchors, FrameRate::default());
    assert_eq!(left.second_poses, vec![1, 4]);
    assert!(left.outliers.is_empty(), "{left:?}");
    // Listed second, the other person is left out as before; without torsos the first
    // pose is the person's.
    let swapped = [0, 1, 2, 3, 5, 4, 6].map(|k| anchors[k]);
    assert_eq!(
        left_out_of_sequence(&frames, &swapped, FrameRate::default()).second_poses,
        vec![1, 5]
    );
    // The other person alone where the person was missed (frame 2) does not become the
    // person: frame 3's first pose, the person's, is within reach of frame 1's.
    let missed_alone = [0, 1, 2, 3, 3, 4].map(Some);
    let poses = [
        at(0.0, 100.0),
        at(20.0, 100.0),
        at(900.0, 100.0),
        at(60.0, 100.0),
        at(905.0, 100.0),
        at(80.0, 100.0),
    ];
    let left = left_out_of_sequence(&missed_alone, &poses, FrameRate::default());
    assert_eq!(left.second_poses, vec![4]);
    let none = [None; 7];
    assert_eq!(
        left_out_of_sequence(&frames, &none, FrameRate::default()).second_poses,
        vec![1, 5]
    );
    // A frame whose poses are all other people's (the person missed by the detector):
    // none of them is the person's.
    let frames = [0, 1, 2, 2, 3].map(Some);
    let missed = [
        at(0.0, 100.0),
        at(20.0, 100.0),
        at(900.0, 100.0),
        at(1300.0, 100.0),
        at(60.0, 100.0),
    ];
    let left = left_out_of_sequence(&frames, &missed, FrameRate::default());
    assert_eq!(left.second_poses, vec![2, 3]);
}

/// A person missed for a few frames is not taken for another person within a torso or three:
/// the reach grows with the time elapsed (a person's step every 1/30 s), not a torso per frame
/// (a simulated user's walker was replaced by a bystander 2.8 torsos away after 3 missed
/// frames, and for good).
#[test]
fn a_person_missed_for_a_moment_is_not_taken_for_a_bystander() {
    for (hz, per_30) in [(30.0, 1u64), (60.0, 2)] {
        let rate = FrameRate::new(hz).unwrap();
        // The walker (10 px a frame at 30 a second), a bystander of half its size 210 px (2.8
        // torsos of their mean) away and a third
        // person far off in every frame; the walker is missed at frames 10-13 (0.13 s).
        let mut frames = Vec::new();
        let mut anchors = Vec::new();
        for t in 0..(30 * per_30) {
            let x = 10.0 * t as f64 / per_30 as f64;
            if !(10 * per_30..14 * per_30).contains(&t) {
                frames.push(Some(t));
                anchors.push(at(x, 100.0));
            }
            for (dx, torso) in [(210.0, 50.0), (3000.0, 90.0)] {
                frames.push(Some(t));
                anchors.push(at(x + dx, torso));
            }
        }
        let left = left_out_of_sequence(&frames, &anchors, rate);
        // The others' poses are all left out, none of the walker's.
        let others: Vec<usize> = (0..anchors.len())
            .filter(|&m| anchors[m].unwrap().torso != 100.0)
            .collect();
        assert_eq!(left.second_poses, others, "{hz} frames a second");
    }
}

/// A sprinter (0.9 torso lengths every 1/30 s) missed for 0.1 s while passing a walker is
/// followed on: where the person is expected carries the sprinter's own velocity (a reach in
/// time from the last pose alone had lost a simulated user's sprinter to the walker).
#[test]
fn a_sprinter_missed_beside_a_walker_is_followed_on() {
    for (hz, per_30) in [(24.0, 1u64), (30.0, 1), (60.0, 2)] {
        let rate = FrameRate::new(hz).unwrap();
        let mut frames = Vec::new();
        let mut anchors = Vec::new();
        for t in 0..(30 * per_30) {
            let s = t as f64 / per_30 as f64;
            // The sprinter is missed at 14-16 (x 1260-1440), passing the walker (farther
            // off, smaller, higher in the image: 2 torsos of their mean from the path).
            if !(14 * per_30..17 * per_30).contains(&t) {
                frames.push(Some(t));
                anchors.push(Some(TorsoAnchor {
                    pelvis: [90.0 * s, 0.0],
                    torso: 100.0,
                }));
            }
            frames.push(Some(t));
            anchors.push(Some(TorsoAnchor {
                pelvis: [1500.0 + 3.0 * s, -160.0],
                torso: 60.0,
            }));
        }
        let left = left_out_of_sequence(&frames, &anchors, rate);
        let sprinter = |m: &usize| anchors[*m].unwrap().torso == 100.0;
        assert!(
            !left.second_poses.iter().any(sprinter),
            "{hz} frames a second: {:?}",
            left.second_poses
        );
        // The walker's poses beside the sprinter's are all left out.
        let beside = (0..anchors.len())
            .filter(|m| !sprinter(m))
            .filter(|&m| frames.iter().filter(|&&f| f == frames[m]).count() == 2)
            .count();
        assert_eq!(left.second_poses.len(), beside, "{hz} frames a second");
    }
}
