//! The publisher's promises to the solver: no subscriber → no frame built; a stalled
//! subscriber → the publisher discards instead of waiting.

use granmix_ipc::pattern::{pattern_info, pattern_record};
use granmix_ipc::{FramePublisher, FrameSubscriber, Outcome};
use iceoryx2::prelude::BackpressureStrategy;

fn unique(tag: &str) -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos();
    format!("test-{tag}-{}-{t}", std::process::id())
}

#[test]
fn without_subscriber_no_frame_is_built() {
    let mut p = FramePublisher::open(&unique("nobody"), 1000).unwrap();
    let mut built = false;
    let out = p.publish_with(&pattern_info(0, 1000), |_| built = true);
    assert_eq!(out, Outcome::NoSubscriber);
    assert!(!built);
    assert_eq!(p.stats().no_subscriber, 1);
}

#[test]
fn a_stalled_subscriber_never_blocks_the_publisher() {
    let svc = unique("stalled");
    let mut p = FramePublisher::open(&svc, 1000).unwrap();
    assert_eq!(p.backpressure(), BackpressureStrategy::DiscardData);
    // subscribes, never takes a frame: its queue fills up after two frames
    let sub = FrameSubscriber::open(&svc).unwrap();
    assert_eq!(p.subscribers(), 1);
    for k in 0..200 {
        let out = p.publish_with(&pattern_info(k, 1000), |recs| {
            for (i, r) in recs.iter_mut().enumerate() {
                *r = pattern_record(k, i);
            }
        });
        // returning at all is the point; a blocking publisher would hang here
        assert!(
            matches!(out, Outcome::Sent(_) | Outcome::Dropped(_)),
            "{out:?}"
        );
    }
    assert_eq!(p.stats().sent + p.stats().dropped, 200);
    // the queue kept the newest frames (overflow drops the oldest)
    let first = sub.receive().unwrap().expect("a frame is waiting");
    assert!(first.header().sequence > 0);
}
