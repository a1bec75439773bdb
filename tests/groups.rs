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
