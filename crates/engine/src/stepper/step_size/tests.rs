use super::*;
use crate::DofLayout;

fn sizes(adaptive: bool) -> StepSizes {
    let ctrl = adaptive.then(|| ErrorController::new(1e-5, 1e-5, 0.05).unwrap());
    StepSizes::new(StepSizing {
        dt: 1e-3,
        min_dt: if adaptive { 1e-5 } else { 1e-3 / 1024.0 },
        adaptive: ctrl,
    })
    .unwrap()
}

#[test]
fn fixed_last_step_lands_exactly_on_the_end() {
    let p = sizes(false);
    // A summed time 1e-10 s short of a whole step: stretched, not followed by a sliver.
    let t = 10.0 - 1e-3 - 1e-10;
    let plan = p.plan(t, 10.0);
    assert_eq!(plan.lands_at, Some(10.0));
    assert_eq!(plan.h, 10.0 - t);
    // A partial last step is shortened; an ordinary one is dt.
    assert_eq!(p.plan(10.0 - 4e-4, 10.0).lands_at, Some(10.0));
    assert_eq!(
        p.plan(9.9, 10.0),
        Plan {
            h: 1e-3,
            lands_at: None
        }
    );
}

#[test]
fn adaptive_steps_end_on_events_without_slivers() {
    let mut p = sizes(true);
    p.state.h = 0.01;
    // Shortened to the event.
    assert_eq!(
        p.plan(1.0, 1.005),
        Plan {
            h: 1.005 - 1.0,
            lands_at: Some(1.005)
        }
    );
    // Less than two steps left: two equal steps, not a step and a 5 ms sliver.
    assert_eq!(p.plan(1.0, 1.015).h, 0.5 * (1.015 - 1.0));
    assert_eq!(p.plan(1.0, 1.015).lands_at, None);
    assert_eq!(p.plan(1.0, 1.03).h, 0.01);
    // Within round-off of the proposal: the proposal itself (same factorisation).
    let plan = p.plan(1.0, 1.0 + 0.01 * (1.0 + 1e-12));
    assert_eq!(plan.h.to_bits(), 0.01f64.to_bits());
    assert!(plan.lands_at.is_some());
}

#[test]
fn adaptive_hold_band_and_shortened_steps() {
    let mut p = sizes(true);
    p.state.h = 0.01;
    // After a step of the proposed size: +10 % is held, +30 % and −10 % are taken.
    p.accepted(0.01, 0.011);
    assert_eq!(p.state.h, 0.01);
    p.accepted(0.01, 0.013);
    assert_eq!(p.state.h, 0.013);
    p.accepted(0.013, 0.0117);
    assert_eq!(p.state.h, 0.0117);
    // After a shortened step the proposal is taken as is (nothing to reuse).
    p.accepted(0.004, 0.0125);
    assert_eq!(p.state.h, 0.0125);
}

#[test]
fn adaptive_failure_halves_and_caps() {
    let mut p = sizes(true);
    p.state.h = 0.008;
    assert!(p.solve_failed(0.008));
    assert_eq!(
        (p.state.h, p.state.cap, p.state.rejected_newton),
        (0.004, 0.004, 1)
    );
    // The controller would grow; the cap holds for GROW_AFTER steps, then doubles.
    for _ in 0..GROW_AFTER - 1 {
        p.accepted(p.state.h, 1.0);
        assert_eq!(p.state.h, 0.004);
    }
    p.accepted(p.state.h, 1.0);
    assert_eq!((p.state.cap, p.state.h), (0.008, 0.008));
    // Once the cap reaches dt_max it is lifted.
    for _ in 0..3 * GROW_AFTER {
        p.accepted(p.state.h, 1.0);
    }
    assert_eq!(p.state.cap, f64::INFINITY);
    // Below dt_min the caller must stop.
    p.state.h = 1.5e-5;
    assert!(!p.solve_failed(1.5e-5));
}

#[test]
fn fixed_failure_halves_and_grows_back() {
    let mut p = sizes(false);
    assert!(p.solve_failed(1e-3));
    assert_eq!(p.state.h, 0.5e-3);
    for _ in 0..GROW_AFTER {
        p.accepted(p.state.h, p.state.h);
    }
    assert_eq!(p.state.h, 1e-3);
    // Ten halvings reach dt/1024; the eleventh goes below.
    for _ in 0..10 {
        assert!(p.solve_failed(p.state.h));
    }
    assert!(!p.solve_failed(p.state.h));
}

#[test]
fn judge_rejects_and_holds_the_retry() {
    let mut p = sizes(true);
    p.state.h = 0.01;
    let mut model = Model::new(DofLayout::new(1, 0));
    model.add_node_mass(0, 1.0);
    let plan = Plan {
        h: 0.01,
        lands_at: None,
    };
    // e = 8e-5 m = 8 tol → reject, retry 0.9/√8 h.
    assert_eq!(p.judge(&model, &[0.0, 0.0, -8e-5], &plan), Err(()));
    assert_eq!(p.state.rejected_error, 1);
    assert!((p.state.h - 0.01 * 0.9 / 8f64.sqrt()).abs() < 1e-12);
    // Within tolerance: accepted with the controller's proposal.
    let plan = Plan {
        h: p.state.h,
        ..plan
    };
    let (next, err) = p.judge(&model, &[0.0, 0.0, -5e-7], &plan).unwrap();
    assert!(err < 1.0 && next > plan.h);
    // A fixed step is never judged.
    let mut f = sizes(false);
    assert!(f.judge(&model, &[0.0, 0.0, -1e3], &plan).is_ok());
}

#[test]
fn bad_sizes_are_errors() {
    for (dt, min) in [(0.0, 1e-6), (1e-3, 0.0), (1e-3, 1e-2), (f64::NAN, 1e-6)] {
        let s = StepSizing {
            dt,
            min_dt: min,
            adaptive: None,
        };
        assert!(StepSizes::new(s).is_err(), "{dt} {min}");
    }
}
