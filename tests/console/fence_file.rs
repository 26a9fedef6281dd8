//! `console::fence_file`: hand-written files before and after a write, and the written files
//! read back with the profile reader (`cli::profiles::parse`, which the console layer itself may
//! not use: hence a test here rather than in the module).

use std::path::{Path, PathBuf};

use armjog::cli::profiles::parse;
use armjog::console::fence_file::{FenceSave, FenceWriteError, write_fence};
use armjog::link::fence::{Aabb, Fence, KeepOut, Singularity};

/// A folder with `config.toml` holding `text`.
fn folder_with(text: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("a folder");
    let file = dir.path().join("config.toml");
    std::fs::write(&file, text).expect("written");
    (dir, file)
}

fn save(file: &Path, arm: &str, fence: &Fence) -> Result<(), FenceWriteError> {
    write_fence(&FenceSave {
        file: file.to_path_buf(),
        arm: arm.into(),
        fence: fence.clone(),
        new_profile: Vec::new(),
    })
}

/// `before` with `arm`'s fence written.
fn written(before: &str, arm: &str, fence: &Fence) -> String {
    let (_dir, file) = folder_with(before);
    save(&file, arm, fence).expect("saved");
    std::fs::read_to_string(&file).expect("read")
}

/// The fence of `arm` as the profile reader reads `text`.
fn read_back(text: &str, arm: &str) -> Fence {
    parse(Path::new("config.toml"), text)
        .expect("loads")
        .get(arm)
        .expect("the arm")
        .fence
        .clone()
        .expect("a fence")
}

fn zone(name: &str, min: [f64; 3], max: [f64; 3], enabled: bool) -> KeepOut {
    KeepOut {
        name: name.into(),
        zone: Aabb { min, max },
        enabled,
    }
}

const CELLS: &str = r#"# armjog arm profiles: one [arms.NAME] table per arm.

# The welding cell.
[arms.cell3]
talos = "192.168.1.20"   # the operator
max_jog_speed = 100

# Its fence, taught on 2 May.
[arms.cell3.fence]
inside = { min = [-600, -600, 0], max = [800, 600, 900] }  # the box the tool stays in
# The gripper, fingers open.
tool_radius = 40          # mm
slow_zone = 60.0          # mm: written as a float, and left so
joints = { j2 = [-120, 120], j4 = [-140, 140] }   # soft limits, degrees
singularity = { slow = 17, stop = 30 }            # the defaults, written

# The table the part lies on.
[[arms.cell3.fence.keep_out]]
name = "table"   # the steel one
min = [250, -400, -100]
max = [900, 400, 80]

# The fixture: off while it is being rebuilt.
[[arms.cell3.fence.keep_out]]
name = "fixture"
min = [0, 300, 0]
max = [100, 400, 200]
enabled = false   # back in June

# The second cell, not fenced yet.
[arms.cell4]
modbus = "192.168.1.11"   # Kinova
# end of profiles
"#;

#[test]
fn comments_and_order_stay_and_only_the_changed_values_are_written() {
    let mut fence = read_back(CELLS, "cell3");
    if let Some(inside) = &mut fence.inside {
        inside.max[2] = 850.5;
    }
    fence.tool_radius = 45.0;
    fence.joints[1] = Some([-125.0, 120.0]);
    fence.joints[3] = None;
    // To a tenth: 95.3.
    fence.keep_out[0].zone.max[2] = 95.25;
    fence.keep_out[1].enabled = true;
    let expected = r#"# armjog arm profiles: one [arms.NAME] table per arm.

# The welding cell.
[arms.cell3]
talos = "192.168.1.20"   # the operator
max_jog_speed = 100

# Its fence, taught on 2 May.
[arms.cell3.fence]
inside = { min = [-600, -600, 0], max = [800, 600, 850.5] }  # the box the tool stays in
# The gripper, fingers open.
tool_radius = 45          # mm
slow_zone = 60.0          # mm: written as a float, and left so
joints = { j2 = [-125, 120] }   # soft limits, degrees
singularity = { slow = 17, stop = 30 }            # the defaults, written

# The table the part lies on.
[[arms.cell3.fence.keep_out]]
name = "table"   # the steel one
min = [250, -400, -100]
max = [900, 400, 95.3]

# The fixture: off while it is being rebuilt.
[[arms.cell3.fence.keep_out]]
name = "fixture"
min = [0, 300, 0]
max = [100, 400, 200]
enabled = true   # back in June

# The second cell, not fenced yet.
[arms.cell4]
modbus = "192.168.1.11"   # Kinova
# end of profiles
"#;
    let after = written(CELLS, "cell3", &fence);
    assert_eq!(after, expected);
    fence.keep_out[0].zone.max[2] = 95.3;
    assert_eq!(read_back(&after, "cell3"), fence);
    // The same fence again: the same text.
    assert_eq!(written(&after, "cell3", &fence), expected);
    // The fence as read: not a byte changes.
    assert_eq!(written(CELLS, "cell3", &read_back(CELLS, "cell3")), CELLS);
}

#[test]
fn written_fences_read_back_the_same() {
    let mut joints = [None; 7];
    joints[0] = Some([-170.0, 170.0]);
    joints[1] = Some([-120.5, 120.0]);
    joints[6] = Some([-10.0, 10.0]);
    let full = Fence {
        inside: Some(Aabb {
            min: [-600.0, -450.5, 0.0],
            max: [800.0, 600.0, 900.1],
        }),
        tool_radius: 12.5,
        slow_zone: 80.0,
        joints,
        singularity: Singularity {
            slow: 20.0,
            stop: 40.5,
        },
        keep_out: vec![
            zone("table", [250.0, -400.0, -100.0], [900.0, 400.0, 80.0], true),
            zone("vice", [-0.5, 0.0, 10.0], [100.2, 50.0, 60.0], false),
            zone("camera \"2\"", [0.0; 3], [1.0; 3], false),
        ],
    };
    let mut fewer = full.clone();
    fewer.inside = None;
    fewer.joints = [None; 7];
    fewer.joints[3] = Some([-140.0, 140.0]);
    fewer.singularity = Singularity::default();
    fewer.keep_out.reverse();
    fewer.keep_out.remove(1);
    fewer.keep_out[1].enabled = true;
    let zones_only = Fence {
        keep_out: vec![zone("post", [1.0; 3], [2.0; 3], false)],
        ..Fence::default()
    };
    let fences = [
        Fence::default(),
        full.clone(),
        fewer,
        zones_only,
        full,
        Fence::default(),
    ];
    let other = "[arms.cell4]\nmodbus = \"192.168.1.11\"\nfence = { tool_radius = 5 }\n";
    let starts = [
        other.to_string(),
        // The fence as an inline table, and as dotted keys.
        format!("[arms.cell3]\nfence = {{ tool_radius = 1, keep_out = [] }}\n{other}"),
        format!("[arms.cell3]\nfence.tool_radius = 1\n{other}"),
        // Its parts as tables of their own.
        format!(
            "[arms.cell3.fence.inside]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n\
             [arms.cell3.fence.joints]\nj5 = [-1, 1]\n{other}"
        ),
    ];
    for start in starts {
        let (_dir, file) = folder_with(&start);
        for fence in &fences {
            save(&file, "cell3", fence).expect("saved");
            let text = std::fs::read_to_string(&file).expect("read");
            assert_eq!(&read_back(&text, "cell3"), fence, "{text}");
            let cell4 = read_back(&text, "cell4");
            assert_eq!(cell4.tool_radius, 5.0, "{text}");
            assert!(
                text.contains("[arms.cell4]\nmodbus = \"192.168.1.11\"\n"),
                "{text}"
            );
        }
    }
}

#[test]
fn a_missing_file_is_made_with_its_folder() {
    let dir = tempfile::tempdir().expect("a folder");
    let file = dir.path().join("armjog").join("config.toml");
    let fence = Fence {
        tool_radius: 40.0,
        ..Fence::default()
    };
    save(&file, "cell3", &fence).expect("saved");
    let text = std::fs::read_to_string(&file).expect("read");
    let expected = "\
[arms.cell3]

[arms.cell3.fence]
tool_radius = 40
slow_zone = 60
";
    assert_eq!(text, expected);
    assert_eq!(read_back(&text, "cell3"), fence);
    // Nothing else is left in the folder (no temporary file).
    let names: Vec<_> = std::fs::read_dir(file.parent().expect("a folder"))
        .expect("listed")
        .map(|e| e.expect("an entry").file_name())
        .collect();
    assert_eq!(names, ["config.toml"]);
}

#[test]
fn a_missing_profile_is_added_at_the_end() {
    let before = r#"# The lab's arms.
[arms.cell4]
modbus = "192.168.1.11"   # Kinova

[arms.cell4.fence]
tool_radius = 30
slow_zone = 60

[arms.cell5]
talos = "192.168.1.30"
# The comments that end the file end it still.
"#;
    let fence = Fence {
        inside: Some(Aabb {
            min: [-500.0, -500.0, 0.0],
            max: [500.0, 500.0, 700.0],
        }),
        tool_radius: 25.0,
        keep_out: vec![zone("tray", [0.0; 3], [100.0, 100.0, 30.5], true)],
        ..Fence::default()
    };
    let expected = r#"# The lab's arms.
[arms.cell4]
modbus = "192.168.1.11"   # Kinova

[arms.cell4.fence]
tool_radius = 30
slow_zone = 60

[arms.cell5]
talos = "192.168.1.30"

[arms.cell3]

[arms.cell3.fence]
inside = { min = [-500, -500, 0], max = [500, 500, 700] }
tool_radius = 25
slow_zone = 60

[[arms.cell3.fence.keep_out]]
name = "tray"
min = [0, 0, 0]
max = [100, 100, 30.5]
# The comments that end the file end it still.
"#;
    let after = written(before, "cell3", &fence);
    assert_eq!(after, expected);
    assert_eq!(read_back(&after, "cell3"), fence);
    // A fence new to a profile goes right after the profile's table.
    let expected = r#"# The lab's arms.
[arms.cell4]
modbus = "192.168.1.11"   # Kinova

[arms.cell4.fence]
tool_radius = 30
slow_zone = 60

[arms.cell5]
talos = "192.168.1.30"

[arms.cell5.fence]
tool_radius = 0
slow_zone = 60
# The comments that end the file end it still.
"#;
    assert_eq!(written(before, "cell5", &Fence::default()), expected);
    let before =
        "[arms.cell4]\ntalos = \"192.168.1.20\"\n\n[arms.cell5]\ntalos = \"192.168.1.30\"\n";
    let expected = "\
[arms.cell4]
talos = \"192.168.1.20\"

[arms.cell4.fence]
tool_radius = 0
slow_zone = 60

[arms.cell5]
talos = \"192.168.1.30\"
";
    assert_eq!(written(before, "cell4", &Fence::default()), expected);
    // A file of comments alone: they head it.
    let expected =
        "# arms\n\n[arms.cell3]\n\n[arms.cell3.fence]\ntool_radius = 0\nslow_zone = 60\n";
    assert_eq!(written("# arms\n\n", "cell3", &Fence::default()), expected);
    // A file without its last newline.
    let expected =
        "[arms.cell4]\ntalos = \"x\"\n\n[arms.cell4.fence]\ntool_radius = 0\nslow_zone = 60\n";
    assert_eq!(
        written("[arms.cell4]\ntalos = \"x\"", "cell4", &Fence::default()),
        expected
    );
}

#[test]
fn zones_are_matched_by_name_and_a_zone_off_says_so() {
    let before = r#"[arms.cell3.fence]
tool_radius = 40
slow_zone = 60

# The table: moved out of the cell.
[[arms.cell3.fence.keep_out]]
name = "table"
min = [250, -400, -100]
max = [900, 400, 80]

# The fixture, soon the jig.
[[arms.cell3.fence.keep_out]]
name = "fixture"
min = [0, 300, 0]
max = [100, 400, 200]

# The vice: off while its jaws are changed.
[[arms.cell3.fence.keep_out]]
name = "vice"   # the small one
min = [-300, 0, 0]
max = [-200, 100, 150]

# The end of the cell.
"#;
    let fence = Fence {
        tool_radius: 40.0,
        keep_out: vec![
            zone("vice", [-300.0, 0.0, 0.0], [-200.0, 100.0, 150.0], false),
            zone("jig", [0.0, 300.0, 0.0], [100.0, 400.0, 250.0], true),
        ],
        ..Fence::default()
    };
    let expected = r#"[arms.cell3.fence]
tool_radius = 40
slow_zone = 60

# The vice: off while its jaws are changed.
[[arms.cell3.fence.keep_out]]
name = "vice"   # the small one
min = [-300, 0, 0]
max = [-200, 100, 150]
enabled = false

[[arms.cell3.fence.keep_out]]
name = "jig"
min = [0, 300, 0]
max = [100, 400, 250]

# The end of the cell.
"#;
    let after = written(before, "cell3", &fence);
    assert_eq!(after, expected);
    assert_eq!(read_back(&after, "cell3"), fence);

    // Reordered: each zone keeps its own comments; they take the places in the fence's order.
    let mut swapped = fence.clone();
    swapped.keep_out.reverse();
    let expected = r#"[arms.cell3.fence]
tool_radius = 40
slow_zone = 60

[[arms.cell3.fence.keep_out]]
name = "jig"
min = [0, 300, 0]
max = [100, 400, 250]

# The vice: off while its jaws are changed.
[[arms.cell3.fence.keep_out]]
name = "vice"   # the small one
min = [-300, 0, 0]
max = [-200, 100, 150]
enabled = false

# The end of the cell.
"#;
    let again = written(&after, "cell3", &swapped);
    assert_eq!(again, expected);
    assert_eq!(read_back(&again, "cell3"), swapped);

    // No zones left: no keep_out.
    let none = Fence {
        keep_out: Vec::new(),
        ..fence
    };
    let expected =
        "[arms.cell3.fence]\ntool_radius = 40\nslow_zone = 60\n\n# The end of the cell.\n";
    assert_eq!(written(&after, "cell3", &none), expected);
}

#[test]
fn inline_zones_stay_inline() {
    let before = r#"[arms.cell3]
fence = { tool_radius = 40, keep_out = [{ name = "table", min = [250, -400, -100], max = [900, 400, 80] }] }
"#;
    let fence = Fence {
        tool_radius: 40.0,
        keep_out: vec![
            zone(
                "table",
                [250.0, -400.0, -100.0],
                [900.0, 400.0, 80.0],
                false,
            ),
            zone("vice", [0.0; 3], [1.0; 3], true),
        ],
        ..Fence::default()
    };
    let expected = r#"[arms.cell3]
fence = { tool_radius = 40, keep_out = [{ name = "table", min = [250, -400, -100], max = [900, 400, 80], enabled = false }, { name = "vice", min = [0, 0, 0], max = [1, 1, 1] }], slow_zone = 60 }
"#;
    let after = written(before, "cell3", &fence);
    assert_eq!(after, expected);
    assert_eq!(read_back(&after, "cell3"), fence);

    let before = r#"[arms.cell3.fence]
keep_out = [
    { name = "table", min = [250, -400, -100], max = [900, 400, 80] },
    { name = "fixture", min = [0, 300, 0], max = [100, 400, 200] },
]
"#;
    let fence = Fence {
        keep_out: vec![
            zone("fixture", [0.0, 300.0, 0.0], [100.0, 400.0, 200.0], true),
            zone("vice", [0.0; 3], [1.0; 3], true),
        ],
        ..Fence::default()
    };
    let expected = r#"[arms.cell3.fence]
keep_out = [
    { name = "fixture", min = [0, 300, 0], max = [100, 400, 200] },
    { name = "vice", min = [0, 0, 0], max = [1, 1, 1] },
]
tool_radius = 0
slow_zone = 60
"#;
    let after = written(before, "cell3", &fence);
    assert_eq!(after, expected);
    assert_eq!(read_back(&after, "cell3"), fence);
}

#[test]
fn a_profile_written_inline_gets_its_fence_inline() {
    let before = "[arms]\ncell3 = { talos = \"192.168.1.20\" }   # the welding cell\n";
    let fence = Fence {
        tool_radius: 40.0,
        keep_out: vec![zone("vice", [0.0; 3], [1.0; 3], false)],
        ..Fence::default()
    };
    let expected = "[arms]\ncell3 = { talos = \"192.168.1.20\", fence = { tool_radius = 40, \
                    slow_zone = 60, keep_out = [{ name = \"vice\", min = [0, 0, 0], max = [1, 1, 1], \
                    enabled = false }] } }   # the welding cell\n";
    let after = written(before, "cell3", &fence);
    assert_eq!(after, expected);
    assert_eq!(read_back(&after, "cell3"), fence);
    // Dotted keys stay dotted.
    let before = "[arms.cell3]\nfence.tool_radius = 40   # mm\n";
    let expected = "[arms.cell3]\nfence.tool_radius = 40   # mm\nfence.slow_zone = 60\n\
                    fence.keep_out = [{ name = \"vice\", min = [0, 0, 0], max = [1, 1, 1], \
                    enabled = false }]\n";
    let after = written(before, "cell3", &fence);
    assert_eq!(after, expected);
    assert_eq!(read_back(&after, "cell3"), fence);
}

#[test]
fn numbers_are_integers_when_whole_else_a_tenth() {
    let fence = Fence {
        inside: Some(Aabb {
            min: [-600.0, -0.04, 12.34],
            max: [899.96, 0.1 + 0.2, 12.5],
        }),
        tool_radius: 12.25,
        slow_zone: 60.0,
        ..Fence::default()
    };
    let expected = "\
[arms.cell3]

[arms.cell3.fence]
inside = { min = [-600, 0, 12.3], max = [900, 0.3, 12.5] }
tool_radius = 12.3
slow_zone = 60
";
    let after = written("", "cell3", &fence);
    assert_eq!(after, expected);
}

#[test]
fn not_toml_is_named_with_its_line_and_the_file_is_kept() {
    let before = "[arms.cell3]\ntalos = \"192.168.1.20\"\nmodbus = \n";
    let (_dir, file) = folder_with(before);
    let err = save(&file, "cell3", &Fence::default()).expect_err("not TOML");
    let message = err.to_string();
    let at = format!(
        "{}:3: fence not saved: the file is not valid TOML",
        file.display()
    );
    assert!(message.starts_with(&at), "{message}");
    assert_eq!(std::fs::read_to_string(&file).expect("read"), before);
}

#[test]
fn an_arm_that_is_not_a_table_is_named() {
    let cases = [
        (
            "[arms]\ncell = 3\n",
            "cell",
            ":2: fence not saved: arms.cell is an integer, not a table",
        ),
        (
            "arms = \"cell3\"\n",
            "cell3",
            ":1: fence not saved: arms is a string, not a table",
        ),
        (
            "[arms.cell3]\nfence = [1]\n",
            "cell3",
            ":2: fence not saved: arms.cell3.fence is an array, not a table",
        ),
    ];
    for (before, arm, said) in cases {
        let (_dir, file) = folder_with(before);
        let err = save(&file, arm, &Fence::default()).expect_err("no table");
        assert_eq!(err.to_string(), format!("{}{said}", file.display()));
        assert_eq!(std::fs::read_to_string(&file).expect("read"), before);
    }
}

#[test]
fn a_folder_that_cannot_be_made_names_the_file() {
    // The folder would be where a regular file is: no permissions needed (root writes anywhere).
    let dir = tempfile::tempdir().expect("a folder");
    let blocker = dir.path().join("armjog");
    std::fs::write(&blocker, "not a folder").expect("written");
    let file = blocker.join("config.toml");
    let err = save(&file, "cell3", &Fence::default()).expect_err("no folder");
    let message = err.to_string();
    let at = format!(
        "{}: fence not saved: cannot make its folder",
        file.display()
    );
    assert!(message.starts_with(&at), "{message}");
    assert!(matches!(err, FenceWriteError::NoFolder { .. }), "{err:?}");
    assert_eq!(
        std::fs::read_to_string(&blocker).expect("read"),
        "not a folder"
    );
}

#[test]
fn a_folder_in_place_of_the_file_is_named() {
    let dir = tempfile::tempdir().expect("a folder");
    let file = dir.path().join("config.toml");
    std::fs::create_dir(&file).expect("made");
    let err = save(&file, "cell3", &Fence::default()).expect_err("a folder");
    let expected = format!(
        "{}: fence not saved: cannot read the file: not a regular file (a directory); only a \
         regular file is read",
        file.display()
    );
    assert_eq!(err.to_string(), expected);
}

#[cfg(unix)]
#[test]
fn a_read_only_folder_names_the_file_and_keeps_it() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, file) = folder_with("[arms.cell3]\n");
    let mode = |m| std::fs::Permissions::from_mode(m);
    std::fs::set_permissions(dir.path(), mode(0o555)).expect("chmod");
    // Root writes anyway: nothing to see there.
    let probe = dir.path().join("probe");
    if std::fs::write(&probe, "").is_ok() {
        std::fs::set_permissions(dir.path(), mode(0o755)).expect("chmod");
        eprintln!("skipped: this user writes into a read-only folder");
        return;
    }
    let err = save(&file, "cell3", &Fence::default()).expect_err("read-only");
    std::fs::set_permissions(dir.path(), mode(0o755)).expect("chmod");
    let at = format!(
        "{}: fence not saved: cannot write the file: ",
        file.display()
    );
    assert!(err.to_string().starts_with(&at), "{err}");
    assert_eq!(
        std::fs::read_to_string(&file).expect("read"),
        "[arms.cell3]\n"
    );
}

#[test]
fn a_fence_that_would_not_load_is_not_written() {
    let (_dir, file) = folder_with(CELLS);
    let mut fence = read_back(CELLS, "cell3");
    fence.keep_out[0].zone.max[0] = f64::INFINITY;
    let err = save(&file, "cell3", &fence).expect_err("refused");
    let expected = format!(
        "{}: fence not saved: arms.cell3.fence.keep_out[1].max: inf is not a finite number",
        file.display()
    );
    assert_eq!(err.to_string(), expected);
    // Apart by less than a tenth: one corner once written.
    let mut fence = read_back(CELLS, "cell3");
    fence.keep_out[0].zone.min[1] = 10.01;
    fence.keep_out[0].zone.max[1] = 10.04;
    let err = save(&file, "cell3", &fence).expect_err("refused");
    assert!(
        err.to_string()
            .ends_with("min 10 is not below max 10 on y (to a tenth, as it would be written)"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&file).expect("read"), CELLS);
}

#[cfg(unix)]
#[test]
fn the_files_permissions_stay_and_a_link_stays_a_link() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, real) = folder_with("[arms.cell3]\n");
    std::fs::set_permissions(&real, std::fs::Permissions::from_mode(0o640)).expect("chmod");
    let link = dir.path().join("link.toml");
    std::os::unix::fs::symlink(&real, &link).expect("linked");
    save(&link, "cell3", &Fence::default()).expect("saved");
    let meta = std::fs::symlink_metadata(&link).expect("the link");
    assert!(meta.file_type().is_symlink());
    let text = std::fs::read_to_string(&real).expect("read");
    assert_eq!(read_back(&text, "cell3"), Fence::default());
    let mode = std::fs::metadata(&real)
        .expect("the file")
        .permissions()
        .mode();
    assert_eq!(mode & 0o777, 0o640);
}

/// A profile made by a write gets the console's link settings; one that exists gets none.
#[test]
fn a_profile_made_by_a_write_gets_the_link_settings_and_one_that_exists_does_not() {
    let (_dir, file) = folder_with("[arms.cell4]\nmodbus = \"192.168.1.11\"\n");
    let settings = vec![
        ("modbus".to_string(), "10.0.0.7:502".to_string()),
        ("unit".to_string(), "1".to_string()),
        ("max_jog_speed".to_string(), "50".to_string()),
    ];
    for arm in ["cell4", "bench"] {
        write_fence(&FenceSave {
            file: file.clone(),
            arm: arm.into(),
            fence: Fence::default(),
            new_profile: settings.clone(),
        })
        .expect("saved");
    }
    let text = std::fs::read_to_string(&file).expect("read");
    let expected = r#"[arms.cell4]
modbus = "192.168.1.11"

[arms.cell4.fence]
tool_radius = 0
slow_zone = 60

[arms.bench]
modbus = "10.0.0.7:502"
unit = 1
max_jog_speed = 50

[arms.bench.fence]
tool_radius = 0
slow_zone = 60
"#;
    assert_eq!(text, expected);
    let profiles = parse(&file, &text).expect("both load");
    assert_eq!(
        profiles.get("bench").expect("bench").value("max_jog_speed"),
        Some("50")
    );
}
