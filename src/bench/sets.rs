//! Instance sets on disk: `count` seeded random instances (instance::generate) written as TOML
//! files, each validated before it is written.

use crate::error::{Error, Result};
use crate::instance::generate::{random_instance, to_toml, GenerateParams};
use crate::instance::Instance;
use std::path::{Path, PathBuf};

/// Parameters of `pushpack generate`.
#[derive(Debug, Clone, PartialEq)]
pub struct SetParams {
    /// Objects per instance.
    pub objects: usize,
    /// Kinds per instance (objects of a kind share their size).
    pub kinds: usize,
    /// Number of instances.
    pub count: usize,
    /// Seed of the first instance; instance `i` uses `seed + i`.
    pub seed: u64,
    /// Container inner width, depth and wall height (m); default the work cell's 0.30 × 0.20 × 0.10.
    pub container: Option<[f64; 3]>,
    /// Range of the horizontal box edges (m); default 0.030–0.060.
    pub size_range: Option<[f64; 2]>,
    /// `any` (default: the placement may lay a box on any face) or `upright` (each box keeps
    /// its table face down, so a top-down grasp can execute every plan without regrasping).
    pub orientations: Option<String>,
}

/// File name of instance `seed` of a set: `n08_k4_s0003.toml`.
pub fn file_name(objects: usize, kinds: usize, seed: u64) -> String {
    format!("n{objects:02}_k{kinds}_s{seed:04}.toml")
}

/// Generate the set into `out` (created if missing); returns the written files in order.
/// Nothing is written when any instance fails validation.
pub fn generate_set(p: &SetParams, out: &Path) -> Result<Vec<PathBuf>> {
    let cli = |field: &str, reason: String| Error::input("<command line>", field, reason);
    if p.count == 0 {
        return Err(cli("--count", "must be at least 1".into()));
    }
    let mut texts = Vec::with_capacity(p.count);
    for i in 0..p.count as u64 {
        let seed = p
            .seed
            .checked_add(i)
            .ok_or_else(|| cli("--seed", "seed + count overflows".into()))?;
        let mut gp = GenerateParams::new(p.objects, p.kinds, seed);
        if let Some(o) = &p.orientations {
            gp.orientations = o.clone();
        }
        if let Some(r) = p.size_range {
            gp.size_range = r;
        }
        let mut f = random_instance(&gp).map_err(|e| {
            let field = if e.starts_with("objects") {
                "--objects"
            } else if e.starts_with("kinds") {
                "--kinds"
            } else {
                "--size-range"
            };
            cli(field, e)
        })?;
        if let Some([w, d, h]) = p.container {
            f.container.width = w;
            f.container.depth = d;
            f.container.wall_height = h;
            if let Some(desc) = f.description.as_mut() {
                desc.push_str(&format!(", container {w} x {d} x {h} m"));
            }
        }
        let text = to_toml(&f);
        let name = file_name(p.objects, p.kinds, seed);
        // Validate in memory so a bad --container or --size-range is reported, not written.
        Instance::parse(&text, false, &name, None).map_err(|e| {
            cli(
                if p.container.is_some() {
                    "--container"
                } else {
                    "--size-range"
                },
                format!("generated instance {name} is invalid: {e}"),
            )
        })?;
        texts.push((name, text));
    }
    std::fs::create_dir_all(out).map_err(|e| Error::Io {
        path: out.to_path_buf(),
        source: e,
    })?;
    let mut written = Vec::new();
    for (name, text) in texts {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| Error::Io {
            path: path.clone(),
            source: e,
        })?;
        written.push(path);
    }
    Ok(written)
}

/// Parse `A,B[,C...]` into exactly `N` positive finite numbers (for `--container`, `--size-range`).
pub fn parse_numbers<const N: usize>(text: &str, field: &str) -> Result<[f64; N]> {
    let bad = |r: String| Error::input("<command line>", field, r);
    let v: Vec<f64> = text
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| bad(format!("{t:?} is not a number")))
        })
        .collect::<Result<_>>()?;
    let arr: [f64; N] = v
        .try_into()
        .map_err(|v: Vec<f64>| bad(format!("needs {N} comma-separated numbers, got {}", v.len())))?;
    if let Some(x) = arr.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        return Err(bad(format!("values must be positive and finite, got {x}")));
    }
    Ok(arr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_are_deterministic_and_valid() {
        let d = tempfile::tempdir().unwrap();
        let p = SetParams {
            objects: 5,
            kinds: 2,
            count: 3,
            seed: 10,
            container: None,
            size_range: Some([0.03, 0.05]),
            orientations: None,
        };
        let a = generate_set(&p, &d.path().join("a")).unwrap();
        let b = generate_set(&p, &d.path().join("b")).unwrap();
        assert_eq!(a.len(), 3);
        assert!(a[2].ends_with("n05_k2_s0012.toml"));
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(std::fs::read(x).unwrap(), std::fs::read(y).unwrap());
            Instance::load(x).unwrap();
        }
    }

    #[test]
    fn upright_sets_keep_every_box_on_its_table_face() {
        let d = tempfile::tempdir().unwrap();
        let mut p = SetParams {
            objects: 6,
            kinds: 3,
            count: 2,
            seed: 1,
            container: None,
            size_range: None,
            orientations: Some("upright".into()),
        };
        for f in generate_set(&p, &d.path().join("up")).unwrap() {
            let inst = Instance::load(&f).unwrap();
            for o in &inst.objects {
                assert!(o.orientations.iter().all(|q| q.up == o.table.up), "{}", f.display());
            }
        }
        // The default lets at least one box of these lie on another face.
        p.orientations = None;
        let any = generate_set(&p, &d.path().join("any")).unwrap();
        let inst = Instance::load(&any[0]).unwrap();
        assert!(inst
            .objects
            .iter()
            .any(|o| o.orientations.iter().any(|q| q.up != o.table.up)));
    }

    #[test]
    fn bad_parameters_name_the_flag() {
        let d = tempfile::tempdir().unwrap();
        let mut p = SetParams {
            objects: 30,
            kinds: 2,
            count: 1,
            seed: 0,
            container: None,
            size_range: None,
            orientations: None,
        };
        assert!(generate_set(&p, d.path())
            .unwrap_err()
            .to_string()
            .contains("--objects"));
        p.objects = 4;
        p.container = Some([0.05, 0.05, 0.1]);
        let e = generate_set(&p, &d.path().join("x")).unwrap_err();
        assert!(e.to_string().contains("--container"), "{e}");
        assert!(!d.path().join("x").exists());
        assert!(parse_numbers::<2>("0.03", "--size-range").is_err());
        assert!(parse_numbers::<2>("0.03,-1", "--size-range").is_err());
        assert_eq!(parse_numbers::<2>("0.03, 0.05", "--size-range").unwrap(), [0.03, 0.05]);
    }
}
