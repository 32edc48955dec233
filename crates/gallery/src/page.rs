//! The gallery's `index.html`: one section per method family, a grid of cards
//! with a picture, its facts and its files. It opens from `file://` anywhere,
//! offline; the only scripts are the 3-D views of mesh cards ([`crate::viewer`]),
//! shipped in the gallery. Cards, pictures and file links fit a phone's width.

use std::fmt::Write as _;

use crate::{Item, Section};

/// `s` with the characters HTML gives a meaning escaped.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The HTML page of `sections`.
pub fn page(sections: &[Section], seed: u64, quick: bool) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>asperity gallery</title>\
<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>\
body{{font-family:system-ui,sans-serif;margin:2rem auto;max-width:1100px;padding:0 1rem;color:#222}}\
h1{{margin-bottom:.2rem}} .meta{{color:#666}} section{{margin-top:2.5rem}}\
.cards{{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(320px,100%),1fr));gap:1rem}}\
.card{{border:1px solid #ddd;border-radius:8px;padding:1rem;background:#fafafa;min-width:0}}\
.card img{{width:100%;image-rendering:pixelated;border-radius:4px;background:#000}}\
.view{{position:relative}} .view model-viewer{{display:block;width:100%;height:auto;aspect-ratio:4/3;border-radius:4px;background:#1b1d22}}\
.turn{{position:absolute;right:.5rem;bottom:.8rem;padding:.3rem .7rem;border:0;border-radius:4px;\
background:#fffd;font:inherit;font-size:.85rem;cursor:pointer}}\
table{{border-collapse:collapse;width:100%;font-size:.9rem;table-layout:fixed}}\
td{{padding:2px 4px;border-bottom:1px solid #eee;overflow-wrap:anywhere}}\
td:first-child{{color:#555;width:38%}} .files{{overflow-wrap:anywhere}} .files a{{margin-right:.6rem;font-size:.9rem}}\
p,h2,h3{{overflow-wrap:anywhere}} @media (max-width:480px){{body{{margin:1rem auto;padding:0 .6rem}}}}</style></head><body>\
<h1>asperity gallery</h1><p class=\"meta\">asperity {} · seed {seed}{} · <a href=\"report.json\">report.json</a></p>",
        env!("CARGO_PKG_VERSION"),
        if quick { " · quick sizes" } else { "" }
    );
    for s in sections {
        let _ = write!(
            h,
            "<section><h2>{}</h2><p class=\"meta\">{}</p><p>{}</p><div class=\"cards\">",
            esc(&s.title),
            esc(&s.source),
            esc(&s.blurb)
        );
        for it in &s.items {
            card(&mut h, it);
        }
        h += "</div></section>";
    }
    if sections
        .iter()
        .flat_map(|s| &s.items)
        .any(|it| it.model.is_some())
    {
        let _ = write!(
            h,
            "<script src=\"{0}/asperity-viewer.js\"></script>",
            crate::viewer::DIR
        );
    }
    h += "</body></html>\n";
    h
}

/// One card: title, picture, facts, files.
fn card(h: &mut String, it: &Item) {
    let _ = write!(h, "<div class=\"card\"><h3>{}</h3>", esc(&it.title));
    let picture = |h: &mut String, img: &str| {
        // lazy: the page loads the pictures in view, not all of them
        let _ = write!(
            h,
            "<img src=\"{}\" alt=\"{}\" loading=\"lazy\">",
            esc(img),
            esc(&it.title)
        );
    };
    match (&it.image, &it.model) {
        (img, Some(model)) => {
            let name = std::path::Path::new(model)
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let _ = write!(
                h,
                "<div class=\"view\" data-name=\"{}\" data-src=\"{}\">",
                esc(&name),
                esc(model)
            );
            if let Some(img) = img {
                picture(h, img);
            }
            *h += "<button class=\"turn\" type=\"button\">Turn in 3D</button></div>";
        }
        (Some(img), None) => picture(h, img),
        (None, None) => {}
    }
    *h += "<table>";
    for (k, v) in &it.facts {
        let _ = write!(h, "<tr><td>{}</td><td>{}</td></tr>", esc(k), esc(v));
    }
    *h += "</table><p class=\"files\">";
    for f in &it.files {
        let _ = write!(h, "<a href=\"{0}\">{0}</a>", esc(f));
    }
    *h += "</p></div>";
}
