//! `propagate`, `eval` and `export` on a tracked folder whose event list of one frame is missing,
//! cut short, or another frame's: each stops with an error naming that frame's event file; a
//! missing or cut list before writing anything, a foreign one before writing its frame.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use surftrack::events::file::decode;

fn surftrack(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_surftrack"))
        .args(args)
        .stdout(Stdio::null())
        .output()
        .unwrap()
}

fn text(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_missing_cut_or_foreign_event_list_is_named_by_every_reader() {
    let tmp = tempfile::tempdir().unwrap();
    let input = tmp.path().join("in");
    let whole = tmp.path().join("whole");
    let synth = surftrack(&[
        "synth",
        "merge",
        "-o",
        text(&input),
        "--resolution",
        "32",
        "--frames",
        "5",
    ]);
    assert!(synth.status.success());
    let tracked = surftrack(&[
        "track",
        text(&input),
        "-o",
        text(&whole),
        "--backend",
        "cpu",
        "--quiet",
    ]);
    assert!(
        tracked.status.success(),
        "{}",
        String::from_utf8_lossy(&tracked.stderr)
    );

    let events = |dir: &Path, k: usize| dir.join(format!("events/{k:04}.events"));
    let original = std::fs::read(events(&whole, 2)).unwrap();
    // The foreign list: a later frame's, which creates vertices frame 2 does not have.
    let foreign = std::fs::read(events(&whole, 4)).unwrap();
    assert!(foreign != original && !decode(&foreign).unwrap().is_empty());

    let damages: [(&str, Option<Vec<u8>>); 3] = [
        ("missing", None),
        ("cut", Some(original[..original.len() / 2].to_vec())),
        ("foreign", Some(foreign)),
    ];
    for (damage, bytes) in damages {
        let dir = tmp.path().join(damage);
        let copy = Command::new("cp")
            .arg("-r")
            .arg(&whole)
            .arg(&dir)
            .status()
            .unwrap();
        assert!(copy.success());
        match bytes {
            None => std::fs::remove_file(events(&dir, 2)).unwrap(),
            Some(bytes) => std::fs::write(events(&dir, 2), bytes).unwrap(),
        }
        let d = text(&dir);
        let ply = tmp.path().join(format!("{damage}-ply"));
        let usd = tmp.path().join(format!("{damage}.usda"));
        let backward = tmp.path().join(format!("{damage}-backward"));
        for args in [
            vec!["propagate", d, "--forward"],
            vec!["propagate", d, "--backward", "-o", text(&backward)],
            vec!["eval", d, "--json", "-"],
            vec!["export", d, "--ply", text(&ply), "--usd", text(&usd)],
        ] {
            let run = surftrack(&args);
            let message = String::from_utf8_lossy(&run.stderr);
            assert!(!run.status.success(), "{damage}: {args:?} succeeded");
            assert!(
                message.contains(&events(&dir, 2).display().to_string()),
                "{damage}: {args:?}: {message}"
            );
        }
        // A missing or cut list is found before anything is written; a foreign one when its
        // frame is reached, so the frames before it (in the direction of travel) are written.
        let written = |folder: &Path| std::fs::read_dir(folder).map_or(0, |d| d.count());
        if damage == "foreign" {
            assert!(!dir.join("propagated/frame_0002.ply").exists());
            assert!(!backward.join("frame_0002.ply").exists());
        } else {
            assert_eq!(written(&dir.join("propagated")), 0, "{damage}");
            assert_eq!(written(&backward), 0, "{damage}");
            assert_eq!(written(&ply), 0, "{damage}");
        }
        assert!(!dir.join("eval.json").exists(), "{damage}");
        assert!(!usd.exists(), "{damage}");
    }
}
