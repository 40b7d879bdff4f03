use super::*;

#[test]
fn cycles_match_by_their_points_and_sets_by_overlap() {
    let a = Reach::Cycle(vec![0.1, 0.5]);
    let tol = SAME_CYCLE;
    assert!(a.same(&Reach::Cycle(vec![0.5 + 1e-6, 0.1]), tol));
    assert!(!a.same(&Reach::Cycle(vec![0.1]), tol));
    assert!(!a.same(&Reach::Cycle(vec![0.1, 0.6]), tol));
    assert!(Reach::Set(0.0, 1.0).same(&Reach::Set(0.9, 2.0), tol));
    assert!(!Reach::Set(0.0, 1.0).same(&Reach::Set(1.1, 2.0), tol));
    assert!(!a.same(&Reach::Set(0.0, 1.0), tol));
    // On a loose map, cycles a few 1e-5 apart are one.
    let loose = same_tol(&crate::sim::default_settings(1e-4));
    assert!(a.same(&Reach::Cycle(vec![0.5 + 3e-5, 0.1]), loose));
    assert!(!a.same(&Reach::Cycle(vec![0.5 + 3e-5, 0.1]), tol));
}

#[test]
fn an_orbit_closing_in_slowly_reaches_its_cycle() {
    // A 3-cycle approached at ratio 0.7 a period, 2e-5 off at first.
    let cycle = [0.3, 0.45, 0.38];
    let orbit: Vec<f64> = (0..60)
        .map(|i| cycle[i % 3] + 2e-5 * 0.7f64.powi((i / 3) as i32) * (1.0 + (i % 3) as f64))
        .collect();
    let settings = crate::sim::default_settings(1e-10);
    let Some(Reach::Cycle(c)) = Reach::of(&orbit, &settings, |c| c.len() == 3) else {
        panic!("not a cycle: {:?}", Reach::of(&orbit, &settings, |_| true));
    };
    assert_eq!(c.len(), 3);
    assert!(
        Reach::Cycle(cycle.to_vec()).same(&Reach::Cycle(c.clone()), SAME_CYCLE),
        "{c:?}"
    );
    for (x, y) in c.iter().zip([cycle[0], cycle[1], cycle[2]]) {
        assert!((x - y).abs() < 1e-12, "{c:?}");
    }
    // Chaos-like wandering does not.
    let wander: Vec<f64> = (0..60)
        .map(|i| 0.3 + 0.1 * ((i * i) as f64).sin())
        .collect();
    assert!(matches!(
        Reach::of(&wander, &settings, |_| true),
        Some(Reach::Set(..))
    ));
    // Nor an orbit closing in where Newton finds no cycle (a chaotic
    // orbit passing a channel).
    assert!(matches!(
        Reach::of(&orbit, &settings, |_| false),
        Some(Reach::Set(..))
    ));
}

#[test]
fn a_branch_continues_to_nearby_points_only() {
    let p2 = Reach::Cycle(vec![0.1, 0.5]);
    // The same P2 a column on, and the P4 it doubled into.
    assert!(continues(&p2, &Reach::Cycle(vec![0.52, 0.11])));
    assert!(continues(&p2, &Reach::Cycle(vec![0.09, 0.12, 0.48, 0.53])));
    // Into a chaotic band about its points.
    assert!(continues(&p2, &Reach::Set(0.08, 0.6)));
    // Not a fixed point, even one near both points, nor a set that
    // misses one point.
    assert!(!continues(&p2, &Reach::Cycle(vec![0.3])));
    let close = Reach::Cycle(vec![0.3, 0.32]);
    assert!(!continues(&close, &Reach::Cycle(vec![0.31])));
    assert!(!continues(&p2, &Reach::Set(0.2, 0.6)));
    // A set continues to an overlapping one, not to a window's cycle.
    assert!(continues(&Reach::Set(0.1, 0.5), &Reach::Set(0.12, 0.53)));
    assert!(!continues(
        &Reach::Set(0.1, 0.5),
        &Reach::Cycle(vec![0.2, 0.3, 0.45])
    ));
}

#[test]
fn labels_grow_with_new_attractors_only() {
    let fp = Reach::Cycle(vec![0.3]);
    let mut col = label(Some(fp.clone()), vec![0.3; 4], vec![], SAME_CYCLE);
    assert_eq!((col.count, col.attractor.clone()), (1, vec![0; 4]));
    let p2 = Reach::Cycle(vec![0.1, 0.5]);
    assert!(col.add(vec![(p2.clone(), vec![0.1, 0.5]), (fp.clone(), vec![0.3])]));
    assert!(!col.add(vec![(p2, vec![0.1, 0.5])]));
    assert_eq!(col.count, 2);
    assert_eq!(col.attractor, vec![0, 0, 0, 0, 1, 1]);
    assert_eq!(col.points_of(1), vec![0.1, 0.5]);
    assert_eq!(col.points_of(2), Vec::<f64>::new());
    let mut set = label(
        Some(Reach::Set(0.1, 0.4)),
        vec![0.1, 0.4, 0.2],
        vec![],
        SAME_CYCLE,
    );
    set.add(vec![(fp.clone(), vec![0.3])]);
    assert_eq!(set.points_of(0), vec![0.2]);
}
