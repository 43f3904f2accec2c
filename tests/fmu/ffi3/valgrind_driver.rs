//! `valgrind_driver_loop3` (ignored): the FMI 3.0 loop that `scripts/valgrind.sh` runs
//! under valgrind.

use super::*;

/// The loop `scripts/valgrind.sh` runs under valgrind (after the FMI 2.0 one).
#[test]
#[ignore = "run by scripts/valgrind.sh"]
fn valgrind_driver_loop3() {
    for round in 0..2 {
        for kind in FmuKind::ALL {
            let (straight, again) = unsafe { life(kind, 40, &format!("valgrind-{round}")) };
            assert_eq!(straight, again);
        }
        // Early return at the breakaway and Event Mode, with every illegal call of the
        // event state table and the state round trips.
        let events = unsafe { event_life(&format!("valgrind-events-{round}"), 0.05, 0.45) };
        assert_eq!(events.straight, events.restored);
    }
    println!(
        "2 rounds x 2 FMUs, and StickSlipBeam with events, through the FMI 3.0 interface done"
    );
}
