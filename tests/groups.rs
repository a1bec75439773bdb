//! Groups in the standalone engine (issue 56, item 2): `group` styles, the memberships follow
//! the atoms through the neighbour list's sorting and through a restart file, and `velocity`
//! and `dump` act on a group only.

use dpdnl::engine::System;

mod common;

const SYSTEM: &str = "units lj\natom_style atomic\nregion box block 0 6 0 6 0 6\n\
    create_box 2 box\ncreate_atoms 1 random 300 4242 box\ncreate_atoms 2 random 100 4343 box\n\
    mass * 1.0\npair_style dpd/nonlinear 1.0 1.0 9898 friction dot\npair_coeff * * 25.0 4.5 0.5\n\
    region left block 0 3 INF INF INF INF\n";

/// The ids of group `name`, sorted.
fn members(sys: &System, name: &str) -> Vec<u32> {
    let bit = sys.groups.bit(name).expect("group exists");
    let a = &sys.atoms;
    let mut t: Vec<u32> = (0..a.len())
        .filter(|&i| a.mask_of(i) & bit != 0)
        .map(|i| a.tag[i])
        .collect();
    t.sort_unstable();
    t
}

fn run(text: &str) -> System {
    common::run(text).expect("script runs").1.expect("a system")
}

/// Each style selects what its definition says, read from the atoms themselves.
#[test]
fn styles_select_what_lammps_selects() {
    let s = run(&format!(
        "{SYSTEM}group t2 type 2\ngroup low id <= 50\ngroup band id 10:40:5\ngroup left region left\n\
         group both intersect t2 left\ngroup either union low band\n\
         group rest subtract all t2 low\ngroup gone empty\ngroup gone delete\n\
         group emptied type 1\ngroup emptied clear\n"
    ));
    let a = &s.atoms;
    let by = |f: &dyn Fn(usize) -> bool| {
        let mut t: Vec<u32> = (0..a.len()).filter(|&i| f(i)).map(|i| a.tag[i]).collect();
        t.sort_unstable();
        t
    };
    assert_eq!(members(&s, "t2"), by(&|i| a.typ[i] == 2));
    assert_eq!(members(&s, "low"), (1..=50).collect::<Vec<_>>());
    assert_eq!(members(&s, "band"), vec![10, 15, 20, 25, 30, 35, 40]);
    let left = |i: usize| a.x[i][0] >= 0.0 && a.x[i][0] <= 3.0;
    assert_eq!(members(&s, "left"), by(&left));
    assert_eq!(members(&s, "both"), by(&|i| a.typ[i] == 2 && left(i)));
    assert_eq!(members(&s, "either"), (1..=50).collect::<Vec<_>>());
    assert_eq!(members(&s, "rest"), by(&|i| a.typ[i] == 1 && a.tag[i] > 50));
    assert!(s.groups.find("gone").is_none());
    assert!(members(&s, "emptied").is_empty());
}

/// Memberships move with the atoms (the list sorts them) and through a restart file; the
/// velocity commands touch the group's atoms only.
#[test]
fn memberships_survive_sorting_restart_and_velocity_acts_on_the_group() {
    let dir = std::env::temp_dir().join(format!("dpdnl-groups-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let file = dir.join("g.restart");
    let s = run(&format!(
        "{SYSTEM}group t2 type 2\ngroup left region left\nvelocity all set 0 0 0\n\
         velocity t2 set 1.0 NULL NULL\nvelocity left create 2.0 777 mom yes\n\
         fix 1 all nve\nrun 20\nwrite_restart {}\n",
        file.display()
    ));
    let before = (members(&s, "t2"), members(&s, "left"));
    let a = &s.atoms;
    let t2: Vec<u32> = {
        let mut t: Vec<u32> = (0..a.len())
            .filter(|&i| a.typ[i] == 2)
            .map(|i| a.tag[i])
            .collect();
        t.sort_unstable();
        t
    };
    assert_eq!(before.0, t2, "the masks followed the atoms' sorting");
    let back = run(&format!("read_restart {}\n", file.display()));
    assert_eq!((members(&back, "t2"), members(&back, "left")), before);
    assert_eq!(back.groups, s.groups);

    // velocity on a group: the others keep theirs.
    let s = run(&format!(
        "{SYSTEM}group left region left\nvelocity all set 0.5 0 0\nvelocity left set 0 2 0\n"
    ));
    let bit = s.groups.bit("left").expect("left");
    for i in 0..s.atoms.len() {
        let want = if s.atoms.mask_of(i) & bit != 0 {
            [0.0, 2.0, 0.0]
        } else {
            [0.5, 0.0, 0.0]
        };
        assert_eq!(s.atoms.v[i], want);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `velocity GROUP create` sets the group's temperature and zero momentum; `dump ID GROUP`
/// writes its atoms only.
#[test]
fn velocity_create_and_dump_on_a_group() {
    let dir = std::env::temp_dir().join(format!("dpdnl-groups-dump-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let dump = dir.join("t2.dump");
    let s = run(&format!(
        "{SYSTEM}group t2 type 2\nvelocity t2 create 1.5 4321\n\
         dump d t2 custom 1 {} id type\nfix 1 all nve\nrun 0\n",
        dump.display()
    ));
    let bit = s.groups.bit("t2").expect("t2");
    let a = &s.atoms;
    let idx: Vec<usize> = (0..a.len()).filter(|&i| a.mask_of(i) & bit != 0).collect();
    let n = idx.len() as f64;
    let mv2: f64 = idx
        .iter()
        .map(|&i| a.v[i].iter().map(|c| c * c).sum::<f64>())
        .sum();
    let t = mv2 / (3.0 * n - 3.0);
    assert!((t - 1.5).abs() < 1e-12, "group temperature {t}");
    for k in 0..3 {
        let p: f64 = idx.iter().map(|&i| a.v[i][k]).sum();
        assert!(p.abs() < 1e-12, "group momentum {p}");
    }
    assert!(
        (0..a.len())
            .filter(|&i| a.mask_of(i) & bit == 0)
            .all(|i| a.v[i] == [0.0; 3])
    );
    let text = std::fs::read_to_string(&dump).expect("dump written");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[3].parse::<usize>().expect("count"), idx.len());
    assert!(lines[9..].iter().all(|l| l.ends_with(" 2")));
    assert_eq!(lines.len(), 9 + idx.len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The tags and states of the atoms of `bit` or not of it.
fn split(s: &System, name: &str) -> (Vec<usize>, Vec<usize>) {
    let bit = s.groups.bit(name).expect("group");
    (0..s.atoms.len()).partition(|&i| s.atoms.mask_of(i) & bit != 0)
}

/// `fix nve` on a group moves its atoms only; `setforce 0 0 0` on a group (applied at the
/// set-up's forces too) leaves its atoms at constant velocity: x(t) = x(0) + t v(0) to
/// round-off.
#[test]
fn an_integrator_on_a_group_and_setforce_zero() {
    let start = run(&format!(
        "{SYSTEM}group t2 type 2\ngroup t1 type 1\nvelocity all create 1.0 99\nrun 0\n"
    ));
    let s = run(&format!(
        "{SYSTEM}group t2 type 2\ngroup t1 type 1\nvelocity all create 1.0 99\n\
         fix 1 t2 nve\nfix 2 t2 setforce 0.0 0.0 0.0\nrun 10\n"
    ));
    let by_tag = |s: &System| {
        let mut v: Vec<_> = (0..s.atoms.len())
            .map(|i| (s.atoms.tag[i], s.atoms.x[i], s.atoms.v[i], s.atoms.image[i]))
            .collect();
        v.sort_by_key(|e| e.0);
        v
    };
    let (a0, a1) = (by_tag(&start), by_tag(&s));
    let l = 6.0;
    let (t2, _) = split(&s, "t2");
    let t2_tags: std::collections::HashSet<u32> = t2.iter().map(|&i| s.atoms.tag[i]).collect();
    for (p, q) in a0.iter().zip(&a1) {
        if t2_tags.contains(&p.0) {
            assert_eq!(
                p.2, q.2,
                "atom {}: the velocity of a forceless atom changed",
                p.0
            );
            for k in 0..3 {
                let unwrapped = |x: [f64; 3], im: [i32; 3]| x[k] + im[k] as f64 * l;
                let moved = unwrapped(q.1, q.3) - unwrapped(p.1, p.3);
                assert!(
                    (moved - 10.0 * s.dt * p.2[k]).abs() < 1e-12,
                    "atom {}: moved {moved}",
                    p.0
                );
            }
        } else {
            assert_eq!(
                (p.1, p.2),
                (q.1, q.2),
                "atom {} outside the group moved",
                p.0
            );
        }
    }
}

/// `fix momentum 1 linear 1 1 1` zeroes the group's momentum at every step's end (to
/// round-off), while the rest of the system keeps exchanging momentum with it.
#[test]
fn momentum_zeroes_the_groups_momentum() {
    let s = run(&format!(
        "{SYSTEM}group t2 type 2\nvelocity all create 1.0 99\nvelocity t2 set 0.5 0.0 0.0 sum yes\n\
         fix 1 all nve\nfix 2 t2 momentum 1 linear 1 1 1\nrun 5\n"
    ));
    let (t2, rest) = split(&s, "t2");
    let p = |idx: &[usize]| {
        let mut p = [0.0; 3];
        for &i in idx {
            for (pk, vk) in p.iter_mut().zip(s.atoms.v[i]) {
                *pk += vk;
            }
        }
        p
    };
    let (pg, pr) = (p(&t2), p(&rest));
    assert!(pg.iter().all(|c| c.abs() < 1e-12), "group momentum {pg:?}");
    assert!(
        pr.iter().any(|c| c.abs() > 1e-6),
        "the rest exchanged none: {pr:?}"
    );
}

/// `fix aveforce NULL NULL 0.0` gives every selected atom the same z force (the average), so
/// after the step the group's atoms all share one z acceleration; x and y are left alone.
#[test]
fn aveforce_sets_the_average() {
    let s = run(&format!(
        "{SYSTEM}group t2 type 2\nfix 1 all nve\nfix 2 t2 aveforce NULL NULL 0.0\nrun 0\n"
    ));
    let (t2, _) = split(&s, "t2");
    let fz: Vec<f64> = t2.iter().map(|&i| s.atoms.f[i][2]).collect();
    assert!(fz.iter().all(|&f| f == fz[0]), "z forces differ");
    let fx: Vec<f64> = t2.iter().map(|&i| s.atoms.f[i][0]).collect();
    assert!(fx.iter().any(|&f| f != fx[0]), "x forces were averaged too");
}

/// `read_data FILE group ID` puts the atoms read into group ID (LAMMPS's keyword).
#[test]
fn read_data_group_keyword() {
    let data =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/crosscheck/dpd3d.data");
    let s = run(&format!(
        "units lj\natom_style atomic\nread_data {} group fluid\n",
        data.display()
    ));
    assert_eq!(members(&s, "fluid").len(), s.atoms.len());
    assert_eq!(s.atoms.len(), 500);
}

/// A run with fixes on groups continues exactly through a restart file: `run 20` + `run 20`
/// gives the same bits as `run 20`, `write_restart`, then `read_restart` (the groups come
/// back from the file), the fixes re-issued, `run 20`.
#[test]
fn fixes_on_groups_restart_exactly() {
    let dir = std::env::temp_dir().join(format!("dpdnl-groups-restart-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch");
    let file = dir.join("g.restart");
    let fixes = "variable fz equal 0.1*cos(0.3*step)\nfix 1 t2 nve\nfix 2 rest nve/euler\n\
                 fix 3 left addforce 0.2 0.0 v_fz every 2\nfix 4 t2 momentum 3 linear 1 1 1\n\
                 fix 5 rest aveforce NULL 0.0 NULL\ntimestep 0.01\n";
    let setup = format!(
        "{SYSTEM}group t2 type 2\ngroup rest subtract all t2\ngroup left region left\n\
         velocity all create 1.0 5\n"
    );
    let straight = run(&format!("{setup}{fixes}run 20\nrun 20\n"));
    run(&format!(
        "{setup}{fixes}run 20\nwrite_restart {}\n",
        file.display()
    ));
    let resumed = run(&format!(
        "read_restart {}\nregion left block 0 3 INF INF INF INF\n{fixes}run 20\n",
        file.display()
    ));
    assert_eq!(
        common::state_by_tag(&straight),
        common::state_by_tag(&resumed)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
