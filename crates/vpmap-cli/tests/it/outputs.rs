//! Issue 40's output paths: a command writes only to regular files or new paths (a FIFO, a
//! device or a folder is refused by name and left as it is), never loses one of its own
//! outputs to another, and never writes a number it cannot read back.

use std::path::{Path, PathBuf};

use super::vpmap;

/// A FIFO at `dir/name`, or `None` where `mkfifo` is missing.
#[cfg(unix)]
fn fifo(dir: &Path, name: &str) -> Option<PathBuf> {
    let path = dir.join(name);
    let made = std::process::Command::new("mkfifo")
        .arg(&path)
        .status()
        .is_ok_and(|s| s.success());
    made.then_some(path)
}

#[cfg(unix)]
fn is_fifo(path: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo())
}

/// Regression: `synth -o FIFO` / `--truth FIFO` renamed a regular file over the FIFO, and
/// (as root) `-o /dev/null` replaced the device.
#[cfg(unix)]
#[test]
fn synth_refuses_a_fifo_or_a_device_as_output_and_leaves_it_alone() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let Some(pipe) = fifo(dir.path(), "pipe") else {
        eprintln!("SKIPPED: mkfifo is not available");
        return;
    };
    let scene = dir.path().join("scene.json");
    let cases: [Vec<&str>; 3] = [
        vec!["synth", "-o", pipe.to_str().unwrap()],
        vec![
            "synth",
            "-o",
            scene.to_str().unwrap(),
            "--truth",
            pipe.to_str().unwrap(),
        ],
        vec![
            "synth",
            "-o",
            scene.to_str().unwrap(),
            "--truth",
            "/dev/null",
        ],
    ];
    for args in cases {
        let o = vpmap(&args);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?} succeeded");
        assert!(
            stderr.contains("it is a FIFO")
                || stderr.contains("/dev/null: it is a character device"),
            "{args:?}: {stderr}"
        );
        assert!(is_fifo(&pipe), "{args:?}: the FIFO was replaced");
        let null = std::fs::metadata("/dev/null").unwrap();
        assert!(null.file_type().is_char_device(), "/dev/null was replaced");
        // Nothing else written: neither the scene nor a truth beside it.
        let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1, "{args:?} wrote files");
    }
}

/// Regression: `detect --out FIFO` replaced the FIFO with the scene file.
#[cfg(unix)]
#[test]
fn detect_refuses_a_fifo_as_output() {
    let dir = tempfile::tempdir().unwrap();
    let Some(pipe) = fifo(dir.path(), "scene.json") else {
        eprintln!("SKIPPED: mkfifo is not available");
        return;
    };
    let rendered = vpmap_vision::synthetic::render_manhattan_scene(
        &vpmap_vision::synthetic::SceneRenderOptions {
            width_px: 200,
            height_px: 150,
            focal_px: 190.0,
            boxes: 3,
            ..vpmap_vision::synthetic::SceneRenderOptions::default()
        },
    );
    let photo = dir.path().join("photo.png");
    rendered.image.save(&photo).unwrap();
    let o = vpmap(&[
        "detect",
        photo.to_str().unwrap(),
        "--out",
        pipe.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && stderr.contains("it is a FIFO"),
        "{stderr}"
    );
    assert!(is_fifo(&pipe));
}

/// `snap -o` a FIFO or a device: refused by name and left as it is, with inputs that snap and
/// write a scene when `-o` is a regular file (so the refusal is the output's, not the inputs').
#[cfg(unix)]
#[test]
fn snap_refuses_a_fifo_or_a_device_as_output_and_leaves_it_alone() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let Some(pipe) = fifo(dir.path(), "snapped.json") else {
        eprintln!("SKIPPED: mkfifo is not available");
        return;
    };
    let scene = dir.path().join("scene.json");
    let o = vpmap(&["synth", "--seed", "3", "-o", scene.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let parsed: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    let (w, h) = (
        u32::try_from(parsed["image"]["width"].as_u64().unwrap()).unwrap(),
        u32::try_from(parsed["image"]["height"].as_u64().unwrap()).unwrap(),
    );
    let photo = dir.path().join("photo.png");
    image::GrayImage::from_pixel(w, h, image::Luma([128]))
        .save(&photo)
        .unwrap();
    let (photo, scene) = (photo.to_str().unwrap(), scene.to_str().unwrap());
    for out in [pipe.to_str().unwrap(), "/dev/null"] {
        let o = vpmap(&["snap", photo, scene, "-o", out]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "snap -o {out} succeeded");
        assert!(
            stderr.contains("it is a FIFO")
                || stderr.contains("/dev/null: it is a character device"),
            "snap -o {out}: {stderr}"
        );
        assert!(is_fifo(&pipe), "snap -o {out}: the FIFO was replaced");
        let null = std::fs::metadata("/dev/null").unwrap();
        assert!(null.file_type().is_char_device(), "/dev/null was replaced");
    }
    // The same inputs to a regular file: written.
    let written = dir.path().join("written.json");
    let o = vpmap(&["snap", photo, scene, "-o", written.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(written.is_file());
}

/// Regression: `synth --truth X -o X` wrote the truth, then the scene over it.
#[test]
fn synth_refuses_one_path_for_the_scene_and_its_truth() {
    let dir = tempfile::tempdir().unwrap();
    let same = dir.path().join("both.json");
    for truth in [same.clone(), dir.path().join(".").join("both.json")] {
        let o = vpmap(&[
            "synth",
            "-o",
            same.to_str().unwrap(),
            "--truth",
            truth.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && stderr.contains("--truth") && stderr.contains("both.json"),
            "{stderr}"
        );
        assert!(!same.exists());
    }
}

/// Regression: `synth --noise 1e308` exited 0 writing `null` coordinates.
#[test]
fn synth_refuses_noise_beyond_its_range() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("scene.json");
    for noise in ["1e308", "1000"] {
        let o = vpmap(&["synth", "--noise", noise, "-o", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && stderr.contains("--noise") && stderr.contains(noise),
            "{noise}: {stderr}"
        );
        assert!(!out.exists());
    }
    // The largest noise accepted still writes numbers.
    let o = vpmap(&["synth", "--noise", "100", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!std::fs::read_to_string(&out).unwrap().contains("null"));
}
