//! `mbfx run --animate FILE.glb|FILE.html` and the flags that go with it (`--glyphs`,
//! `--geometry`; `--interpolate[=FPS]` is `run`'s own): the session's
//! [`AnimationRequest`] from them, checked before the run (a target of an unknown kind,
//! a geometry map that cannot be read), and the file written once the run is over,
//! through a temporary file beside it renamed into place, so that a failure leaves
//! nothing half-written. `--geometry` is parsed here once for both its uses: the
//! meshes the animation draws and the EXTERNAL geometry of CONTACTs, which a run reads
//! with or without `--animate`.

use crate::session::animation::{Animation, AnimationRequest, DEFAULT_FPS};
use std::path::{Path, PathBuf};

/// The animation's flags.
#[derive(clap::Args, Debug, Default)]
pub struct AnimateArgs {
    /// Write the mechanism's animation: FILE.glb (glTF 2.0 binary, in meters with +Y up)
    /// or FILE.html (a self-contained page: the viewer, the .glb and the run's columns
    /// inlined). Frames come at each output row; --interpolate[=FPS] makes them FPS per
    /// second of model time (default 60) from the integrator's continuous extension,
    /// leaving the rows as they are.
    #[arg(long, value_name = "FILE")]
    pub animate: Option<PathBuf>,
    /// With --animate: glyphs for every part (inertia ellipsoid, links to the joint
    /// markers, joint symbols), not only for parts with nothing to draw.
    #[arg(long, requires = "animate")]
    pub glyphs: bool,
    /// A mesh (STL, OBJ, glTF) for an EXTERNAL graphic as GRAPHICS/ID=FILE, or a TOML
    /// file mapping many ("GRAPHICS/12" = "crank.stl", paths relative to it);
    /// repeatable. A CONTACT naming the graphic collides with the mesh; --animate draws
    /// it.
    #[arg(long, value_name = "GRAPHICS/ID=FILE|MAP.toml")]
    pub geometry: Vec<String>,
}

/// What the target's extension asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Glb,
    Html,
}

impl AnimateArgs {
    /// The kind of file --animate names, and the session's request (`interpolate`: the
    /// --interpolate flag, with its rate if given); None without --animate. A rate
    /// without --animate is an error: it is the animation's.
    pub fn request(
        &self,
        interpolate: Option<Option<f64>>,
    ) -> Result<Option<(Kind, AnimationRequest)>, String> {
        let Some(path) = &self.animate else {
            if let Some(Some(fps)) = interpolate {
                return Err(format!(
                    "--interpolate={fps} sets the animation's frame rate: it needs --animate FILE.glb|FILE.html"
                ));
            }
            return Ok(None);
        };
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let kind = match ext.as_deref() {
            Some("glb") => Kind::Glb,
            Some("html" | "htm") => Kind::Html,
            _ => {
                return Err(format!(
                    "--animate {}: the file kinds known are .glb (glTF 2.0 binary) and .html (a self-contained page)",
                    path.display()
                ))
            }
        };
        let request = AnimationRequest {
            fps: interpolate.map(|f| f.unwrap_or(DEFAULT_FPS)),
            glyphs: self.glyphs,
            geometry: self.geometry()?,
        };
        Ok(Some((kind, request)))
    }

    /// The meshes `--geometry` gives (GRAPHICS id, file), in the order given; an
    /// argument that is neither GRAPHICS/ID=FILE nor a readable TOML map is an error.
    pub fn geometry(&self) -> Result<Vec<(u32, PathBuf)>, String> {
        let mut geometry = Vec::new();
        for g in &self.geometry {
            geometry.extend(geometry_of(g)?);
        }
        Ok(geometry)
    }
}

/// `GRAPHICS/ID=FILE`, or the pairs of a TOML map file.
fn geometry_of(arg: &str) -> Result<Vec<(u32, PathBuf)>, String> {
    if let Some((id, file)) = arg.split_once('=') {
        return Ok(vec![(
            graphics_id(id).ok_or_else(|| bad_spec(arg))?,
            file.into(),
        )]);
    }
    let path = Path::new(arg);
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
    {
        return Err(bad_spec(arg));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("--geometry {arg}: cannot read it: {e}"))?;
    let table: toml::Table =
        toml::from_str(&text).map_err(|e| format!("--geometry {arg}: {}", e.message()))?;
    let dir = path.parent().unwrap_or(Path::new(""));
    (table.iter())
        .map(|(key, value)| {
            let id = graphics_id(key)
                .ok_or_else(|| format!("--geometry {arg}: `{key}` is not GRAPHICS/ID"))?;
            let file = value
                .as_str()
                .ok_or_else(|| format!("--geometry {arg}: {key} must name a file (a string)"))?;
            Ok((id, dir.join(file)))
        })
        .collect()
}

fn bad_spec(arg: &str) -> String {
    format!(
        "--geometry {arg}: expected GRAPHICS/ID=FILE or a .toml file mapping GRAPHICS/ID to files"
    )
}

/// The id of `GRAPHICS/ID` (any case, blanks around).
fn graphics_id(s: &str) -> Option<u32> {
    let (kind, id) = s.trim().split_once('/')?;
    kind.eq_ignore_ascii_case("GRAPHICS")
        .then(|| id.trim().parse().ok())
        .flatten()
}

/// Writes `animation` to `path` as `kind` asks (the page's chart from `header` and
/// `rows`), through a temporary file beside it renamed into place.
pub fn write(
    path: &Path,
    kind: Kind,
    animation: &Animation,
    header: &[String],
    rows: &[Vec<f64>],
) -> std::io::Result<()> {
    let bytes = match kind {
        Kind::Glb => animation.glb(),
        Kind::Html => animation.html(header, rows).into_bytes(),
    };
    let name = path
        .file_name()
        .map_or_else(|| "animation".into(), |n| n.to_string_lossy().into_owned());
    let temporary = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let written =
        std::fs::write(&temporary, bytes).and_then(|()| std::fs::rename(&temporary, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    written
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(animate: &str, geometry: &[&str]) -> AnimateArgs {
        AnimateArgs {
            animate: Some(animate.into()),
            glyphs: false,
            geometry: geometry.iter().map(|g| g.to_string()).collect(),
        }
    }

    #[test]
    fn the_extension_says_the_kind_and_others_are_refused() {
        let glb = args("a.GLB", &[]).request(None).unwrap().unwrap();
        assert_eq!(glb.0, Kind::Glb);
        assert_eq!(glb.1.fps, None);
        let html = args("a.html", &[]).request(Some(None)).unwrap().unwrap();
        assert_eq!((html.0, html.1.fps), (Kind::Html, Some(60.0)));
        let e = args("a.gltf", &[]).request(None).unwrap_err();
        assert!(e.contains(".glb") && e.contains(".html"), "{e}");
        let none = AnimateArgs::default();
        assert!(none.request(Some(Some(30.0))).is_err());
        assert!(none.request(Some(None)).unwrap().is_none());
    }

    #[test]
    fn geometry_is_an_id_and_a_file_or_a_map() {
        let dir = std::env::temp_dir().join(format!("mbfx-geometry-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let map = dir.join("map.toml");
        std::fs::write(
            &map,
            "\"GRAPHICS/12\" = \"crank.stl\"\n\"graphics/3\" = \"/abs/b.obj\"\n",
        )
        .unwrap();
        let a = args("a.glb", &["GRAPHICS/7=x.stl", map.to_str().unwrap()]);
        let (_, r) = a.request(None).unwrap().unwrap();
        let mut g = r.geometry;
        g.sort();
        assert_eq!(
            g,
            [
                (3, PathBuf::from("/abs/b.obj")),
                (7, PathBuf::from("x.stl")),
                (12, dir.join("crank.stl"))
            ]
        );
        assert!(args("a.glb", &["PART/7=x.stl"]).request(None).is_err());
        assert!(args("a.glb", &["missing.toml"])
            .request(None)
            .unwrap_err()
            .contains("missing.toml"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
