//! `closed.toml` in SIMD lanes: the offset slot (RPR), the inclined slide (RRP) and the cross
//! slide (two lengths), the kinds whose lane kernels no compiled-in file of the root crate
//! reaches, held to their scalar ticks bit for bit by the root crate's lane check
//! (`tests/common/lanes.rs`: random params and input rates per lane, the last lane up to 90 % off
//! so that it meets these mechanisms' dead points; every lane's status and state the scalar
//! tick's).

#[allow(dead_code)]
#[path = "../../common/lanes.rs"]
mod lanes;

use mechgen::StaticMechanism;
use mechgen_odd_files::closed::{cross_slide, inclined_slide, offset_slot};

fn check<M: StaticMechanism<f64>>(m: &M) -> lanes::Seen {
    let mut seen = lanes::Seen::default();
    if let Err(e) = lanes::check_mechanism_lanes(m, 0.9, 24, 400, &mut seen) {
        panic!("{e}");
    }
    eprintln!("{}: {seen:?}", m.info().name);
    assert!(seen.compared > 0);
    seen
}

#[test]
fn offset_slot_lanes_are_its_scalar_ticks() {
    let seen = check(&offset_slot::OffsetSlot::<f64>::default());
    assert!(seen.failed > 0 && seen.ok_beside_failed > 0, "{seen:?}");
}

#[test]
fn inclined_slide_lanes_are_its_scalar_ticks() {
    let seen = check(&inclined_slide::InclinedSlide::<f64>::default());
    assert!(seen.failed > 0 && seen.ok_beside_failed > 0, "{seen:?}");
}

#[test]
fn cross_slide_lanes_are_its_scalar_ticks() {
    // Two lengths have no dead point: every lane of every case is ok.
    let seen = check(&cross_slide::CrossSlide::<f64>::default());
    assert_eq!(seen.failed, 0, "{seen:?}");
}
