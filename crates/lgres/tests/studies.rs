//! The studies are consistent values: their claims judge scenes the study runs, a
//! paper-formulation study mirrors every scene of a physical one, and the paper's numbers are
//! filed under names the studies find.

use lgres::claim::Cases;
use lgres::paper::paper;
use lgres::scenes;
use lgres::studies::{EXTRAPOLATION, STUDIES, Study, study};

fn scene_stages(name: &str) -> usize {
    let s = scenes::builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
    s.run.wear_stages as usize
}

#[test]
fn names_are_unique_and_found() {
    for (k, s) in STUDIES.iter().enumerate() {
        assert!(
            STUDIES[..k].iter().all(|other| other.name != s.name),
            "{} twice",
            s.name
        );
        assert_eq!(study(s.name).map(|found| found.name), Some(s.name));
    }
    assert!(study("nope").is_none());
}

#[test]
fn every_claim_judges_scenes_its_study_runs() {
    for s in STUDIES {
        let cases = s.claim.cases;
        for scene in cases.scenes() {
            assert!(s.scenes.contains(&scene), "{}: {scene} not run", s.name);
        }
        assert!(!s.claim.trend.is_empty(), "{}", s.name);
        match cases {
            Cases::Scenes {
                first,
                second,
                response,
            } => {
                assert_ne!(first, second, "{}", s.name);
                assert!(
                    !(response.is_empty() && s.claim.wear.is_empty()),
                    "{}",
                    s.name
                );
            }
            Cases::Stages {
                scene,
                first,
                second,
            } => {
                assert!(
                    1 <= first && first < second,
                    "{}: stages {first}, {second}",
                    s.name
                );
                assert!(
                    second <= scene_stages(scene),
                    "{}: {scene} has too few stages",
                    s.name
                );
                assert!(!s.claim.wear.is_empty(), "{}", s.name);
            }
        }
    }
}

/// A mirror names a physical study and maps each scene of the mirroring study to one of its
/// scenes, once; the claim is the same trend on the mirrored cases.
#[test]
fn every_mirror_covers_its_study_scene_by_scene() {
    let mirrored = |s: &Study, scene: &str| -> String {
        let m = s.mirror.expect("a mirror");
        let pairs: Vec<_> = m.scenes.iter().filter(|(ours, _)| *ours == scene).collect();
        assert_eq!(pairs.len(), 1, "{}: {scene} mirrored once", s.name);
        pairs[0].1.to_string()
    };
    let mut mirrors = 0;
    for s in STUDIES {
        let Some(m) = s.mirror else {
            assert_eq!(s.paper_name(), s.name);
            continue;
        };
        mirrors += 1;
        assert!(m.study.mirror.is_none(), "{} mirrors a mirror", s.name);
        assert_eq!(study(m.study.name).map(|p| p.name), Some(m.study.name));
        assert_eq!(s.paper_name(), m.study.name);
        assert_eq!(m.scenes.len(), s.scenes.len(), "{}", s.name);
        for scene in s.scenes {
            let theirs = mirrored(s, scene);
            assert!(
                m.study.scenes.contains(&theirs.as_str()),
                "{}: {theirs}",
                s.name
            );
            assert_eq!(s.scene_for(&theirs), Some(*scene));
        }
        assert_eq!(s.claim.trend, m.study.claim.trend, "{}", s.name);
        let ours: Vec<String> = s
            .claim
            .cases
            .scenes()
            .iter()
            .map(|c| mirrored(s, c))
            .collect();
        assert_eq!(ours, m.study.claim.cases.scenes(), "{}", s.name);
    }
    assert_eq!(mirrors, 3, "the three paper-formulation studies");
}

/// Every study the paper files numbers under is a physical study, and every study finds the
/// scene standing for each of their scenes.
#[test]
fn the_papers_numbers_are_found_by_every_study_filed_under_them() {
    let filed = paper().expect("paper.toml parses");
    for p in filed {
        let physical = study(&p.name).unwrap_or_else(|| panic!("no study {}", p.name));
        assert!(physical.mirror.is_none(), "{}", p.name);
        let readers: Vec<&Study> = STUDIES
            .iter()
            .filter(|s| s.paper_name() == p.name)
            .collect();
        assert!(
            readers.len() >= 2,
            "{}: physical and paper formulation",
            p.name
        );
        for s in readers {
            for v in &p.values {
                assert!(s.scene_for(&v.scene).is_some(), "{}: {}", s.name, v.scene);
            }
        }
    }
}

/// The extrapolation study runs a built-in scene, and its single-jump run's key (a folder
/// name) is no scene's and no study's.
#[test]
fn the_extrapolation_study_has_a_key_of_its_own() {
    let e = EXTRAPOLATION;
    assert!(scenes::source(e.scene).is_some(), "{}", e.scene);
    assert!(scenes::source(e.single_jump_run).is_none());
    assert!(study(e.name).is_none(), "{} is also a paper study", e.name);
    for s in STUDIES {
        assert!(!s.scenes.contains(&e.single_jump_run), "{}", s.name);
    }
}
