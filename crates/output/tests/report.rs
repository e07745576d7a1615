//! `report.html`: every figure of the run embedded byte for byte, every verdict shown, nothing
//! fetched from elsewhere, text escaped; the study and markdown pages embed their images.

mod common;

use std::path::{Path, PathBuf};

use output::html::{self, Html, Td};

fn temp_dir(tag: &str) -> PathBuf {
    common::temp_dir("report", tag)
}

/// Every `src="…"` attribute of `page`.
fn sources(page: &str) -> Vec<&str> {
    page.split("src=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .collect()
}

fn images_in(dir: &Path) -> Vec<PathBuf> {
    let mut images: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| html::image_mime(p).is_some())
        .collect();
    images.sort();
    images
}

/// A short worn slider-crank run whose description needs escaping.
#[test]
fn a_run_report_embeds_every_figure_and_shows_every_verdict() {
    let text = common::worn_slider_crank(
        "description = \"crank <b>fast</b> & \\\"worn\\\"\"\n",
        2,
        1,
        "clearance_limit = 0.000505\n",
    );
    let outcome = common::run(&text, "report");
    let dir = temp_dir("run");
    let files = output::write_run(&outcome, &dir).unwrap();
    let report = dir.join("report.html");
    assert_eq!(files.last(), Some(&report), "the report is written last");
    let page = std::fs::read_to_string(&report).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>"));

    // Self-contained: every source is a data URI, no address of another host anywhere.
    let srcs = sources(&page);
    assert!(srcs.iter().all(|s| s.starts_with("data:")), "{:?}", &srcs);
    for scheme in ["http://", "https://", "//cdn", "<script"] {
        assert!(!page.contains(scheme), "page contains {scheme}");
    }
    // Every image the run wrote is in the page, byte for byte, and nothing else is.
    let images = images_in(&dir);
    assert!(images.len() >= 8, "{images:?}");
    for gif in ["mechanism.gif", "mechanism_worn.gif"] {
        assert!(dir.join(gif).is_file(), "{gif} missing: {images:?}");
    }
    assert_eq!(srcs.len(), images.len());
    for image in &images {
        let mime = html::image_mime(image).unwrap();
        let uri = html::data_uri(mime, &std::fs::read(image).unwrap());
        assert!(page.contains(&uri), "{} not embedded", image.display());
    }

    // Every verdict: validity and energy books for each joint of each response.
    let s = &outcome.summary;
    let responses = [Some(&s.response), s.worn_response.as_ref()];
    let joints: Vec<_> = responses.iter().flatten().flat_map(|r| &r.joints).collect();
    assert_eq!(joints.len(), 2);
    let inside = page.matches("<td class=\"ok\">inside (").count();
    let outside = page.matches("<td class=\"bad\">OUTSIDE: ").count();
    assert_eq!(
        inside + outside,
        joints.len(),
        "one validity verdict per joint"
    );
    let expected_outside = joints
        .iter()
        .filter(|j| j.validity.as_ref().is_some_and(|v| !v.inside))
        .count();
    assert_eq!(outside, expected_outside);
    let books = page.matches(">close</td>").count() + page.matches(">DO NOT close</td>").count();
    assert_eq!(books, joints.len(), "one energy verdict per joint");
    for heading in [
        "Contact force peaks",
        "Deviation of slider from the ideal mechanism",
        "Energy books, per cycle",
        "Wear",
        "Numerics",
        "Figures",
        "Scene parameters",
        "Files",
    ] {
        assert!(page.contains(&format!("<h2>{heading}</h2>")), "{heading}");
    }
    // The wear peak in µm as the table prints it (with its noise when measured), the
    // clearance limit's verdict, the warnings.
    let wear = &s.wear.as_ref().unwrap().joints[0];
    let peak = output::report::sig(wear.bearing_peak_depth_m * 1e6, 3);
    let printed = match wear.bearing_peak_depth_noise_m {
        Some(n) => format!(">{peak} ± {} µm<", output::report::sig(n * 1e6, 2)),
        None => format!(">{peak} µm<"),
    };
    assert!(page.contains(&printed), "bearing peak {printed}");
    assert!(wear.noise_batches > 0, "this stage keeps its halves");
    assert!(page.contains(&format!(
        "a standard error over {} batches",
        wear.noise_batches
    )));
    assert!(page.contains("505 µm"), "clearance limit shown");
    for w in &s.wear.as_ref().unwrap().warnings {
        assert!(page.contains(&html::escape(w)), "warning {w}");
    }
    // Captions read as sentences: no runs of spaces (a broken string continuation shows so).
    for caption in page.split("<figcaption>").skip(1) {
        let caption = caption.split("</figcaption>").next().unwrap();
        assert!(!caption.contains("  "), "{caption}");
    }
    assert_eq!(page.matches("<figcaption>mechanism").count(), 2);
    // Escaped: the description's markup is text, not markup.
    assert!(page.contains("crank &lt;b&gt;fast&lt;/b&gt; &amp; &quot;worn&quot;"));
    assert!(!page.contains("<b>fast"));
    // Scene parameters, with units.
    assert!(page.contains("<td>bodies[0].mass</td><td>0.3</td><td>kg</td>"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A stage that measured no noise (one cycle a run: no halves) says so, rather than giving
/// a standard error over no batches.
#[test]
fn a_stage_without_noise_says_none_was_measured() {
    let text = common::worn_slider_crank("", 1, 1, "").replace(
        "cycles_per_stage = 2\namplification = 750.0",
        "cycles_per_stage = 1\namplification = 1500.0",
    );
    let outcome = common::run(&text, "no-noise");
    let wear = outcome.summary.wear.as_ref().unwrap();
    assert!(
        wear.joints
            .iter()
            .all(|j| j.noise_batches == 0 && j.bearing_peak_depth_noise_m.is_none())
    );
    let dir = temp_dir("no-noise");
    output::write_run(&outcome, &dir).unwrap();
    let page = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(page.contains("no sampling noise was measured"));
    assert!(!page.contains("batches of the runs"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scene without clearance joints runs the kinematic path: no force or energy tables, and
/// the numerics say why; `run.animation = false` draws no animation.
#[test]
fn a_kinematic_run_reports_without_contact_tables() {
    let scene = lgres::scenes::builtin("lgres-ideal")
        .unwrap()
        .edit("lgres-ideal, one cycle", |s| {
            s.run.cycles = 1;
            s.run.animation = false;
        })
        .unwrap();
    let outcome = sim::run_scene("lgres-ideal", &scene, &Default::default(), &mut ()).unwrap();
    let dir = temp_dir("ideal");
    output::write_run(&outcome, &dir).unwrap();
    let page = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(!page.contains("<h2>Contact force peaks</h2>"));
    assert!(!page.contains("<h2>Energy books, per cycle</h2>"));
    assert!(page.contains("Kinematic analysis only"));
    assert!(!dir.join("mechanism.gif").exists());
    assert_eq!(sources(&page).len(), images_in(&dir).len());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Markdown pages (the study report) embed their local images and keep links; an image that
/// is not a plain relative file is left as it is.
#[test]
fn markdown_pages_embed_local_images_and_render_tables() {
    let dir = temp_dir("md");
    let png = dir.join("figure.png");
    output::plot::line_chart(
        &png,
        &output::plot::Figure {
            title: "t",
            x_label: "x",
            y_label: "y",
            size: (200, 150),
        },
        &[output::plot::Series {
            label: "s",
            x: &[0.0, 1.0],
            y: &[0.0, 1.0],
        }],
    )
    .unwrap();
    let md = "# Title\n\n| a | b |\n|---|---|\n| 1 | 2 |\n\n![figure](figure.png)\n\n\
              [scene](lgres/report.html)\n\n![up](../x.png)\n";
    html::write_markdown_and_page(&dir, "page", md, "T <1>").unwrap();
    assert_eq!(std::fs::read_to_string(dir.join("page.md")).unwrap(), md);
    let page = std::fs::read_to_string(dir.join("page.html")).unwrap();
    assert!(page.contains("<title>T &lt;1&gt;</title>"));
    assert!(page.contains("<table>") && page.contains("<td>2</td>"));
    let uri = html::data_uri("image/png", &std::fs::read(&png).unwrap());
    assert!(page.contains(&format!("src=\"{uri}\"")));
    assert!(page.contains("href=\"lgres/report.html\""));
    assert!(
        page.contains("src=\"../x.png\""),
        "a path leaving the folder is not read"
    );
    // A missing local image is an error naming it, not a page with a hole.
    let err = html::write_markdown_and_page(&dir, "bad", "![m](missing.png)", "t").unwrap_err();
    assert!(err.to_string().contains("missing.png"), "{err}");
    // Tables built in code escape their cells.
    let mut h = Html::new();
    h.table(&["<h>"], &[vec![Td::text("a&b")]]);
    assert!(
        h.fragment().contains("<th>&lt;h&gt;</th>") && h.fragment().contains("<td>a&amp;b</td>")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
