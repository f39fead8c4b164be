//! `index.html` of an output folder: the run's summary (the lines the command prints) and every
//! chart it wrote, linked relatively so the folder can be moved or served as it is. A small inline
//! script checks, once the page has loaded, that every chart loaded with a non-zero size and says
//! so at the top of the page (`#chart-check`, also in its `data-total` and `data-broken`
//! attributes, which the browser test reads).

use crate::atomic_file::AtomicFile;
use crate::error::ChartError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The file name of the page.
pub const FILE: &str = "index.html";

/// The page's id of the check result.
pub const CHECK_ID: &str = "chart-check";

/// Escapes text for HTML content and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// `file` relative to `dir` (its file name if it is not inside), with `/` separators.
fn relative(dir: &Path, file: &Path) -> String {
    let rel = file
        .strip_prefix(dir)
        .ok()
        .filter(|r| !r.as_os_str().is_empty())
        .or_else(|| file.file_name().map(Path::new))
        .unwrap_or(file);
    rel.components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

const CHECK_SCRIPT: &str = r#"<script>
window.addEventListener("load", function () {
  var imgs = document.querySelectorAll("img");
  var broken = [];
  imgs.forEach(function (i) {
    if (!(i.complete && i.naturalWidth > 0 && i.naturalHeight > 0)) broken.push(i.getAttribute("src"));
  });
  var p = document.getElementById("chart-check");
  p.setAttribute("data-total", String(imgs.length));
  p.setAttribute("data-broken", broken.join(" "));
  p.textContent = broken.length
    ? "Charts that did not load: " + broken.join(", ")
    : "All " + imgs.length + " charts loaded.";
  p.className = broken.length ? "bad" : "ok";
});
</script>"#;

const STYLE: &str = "<style>\
body{font-family:sans-serif;margin:1.5em;max-width:1200px;color:#222}\
pre{background:#f4f4f4;padding:.8em;overflow-x:auto}\
figure{margin:1.5em 0}img{max-width:100%;border:1px solid #ddd}\
figcaption{color:#555;font-size:.9em}.bad{color:#b00;font-weight:bold}.ok{color:#070}\
</style>";

/// The page: `title`, the `summary` text, the SVG `files` as figures and the others as links.
pub fn html(dir: &Path, title: &str, summary: &str, files: &[PathBuf]) -> String {
    let mut h = String::new();
    h.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    h.push_str(&format!(
        "<title>{}</title>\n{STYLE}\n</head>\n<body>\n",
        escape(title)
    ));
    h.push_str(&format!("<h1>{}</h1>\n", escape(title)));
    h.push_str(&format!(
        "<p id=\"{CHECK_ID}\">Checking the charts (needs JavaScript).</p>\n"
    ));
    h.push_str(&format!(
        "<h2>Summary</h2>\n<pre>{}</pre>\n",
        escape(summary)
    ));
    let (charts, others): (Vec<&PathBuf>, Vec<&PathBuf>) = files
        .iter()
        .partition(|f| f.extension().is_some_and(|e| e == "svg"));
    if !others.is_empty() {
        h.push_str("<h2>Data</h2>\n<ul>\n");
        for f in others {
            let rel = escape(&relative(dir, f));
            h.push_str(&format!("<li><a href=\"{rel}\">{rel}</a></li>\n"));
        }
        h.push_str("</ul>\n");
    }
    h.push_str("<h2>Charts</h2>\n");
    for f in charts {
        let rel = escape(&relative(dir, f));
        h.push_str(&format!(
            "<figure><a href=\"{rel}\"><img src=\"{rel}\" alt=\"{rel}\"></a>\
             <figcaption>{rel}</figcaption></figure>\n"
        ));
    }
    h.push_str(CHECK_SCRIPT);
    h.push_str("\n</body>\n</html>\n");
    h
}

/// Writes [`html`] to `dir/index.html` atomically; returns its path.
pub fn write(
    dir: &Path,
    title: &str,
    summary: &str,
    files: &[PathBuf],
) -> Result<PathBuf, ChartError> {
    let path = dir.join(FILE);
    let fail = |e: std::io::Error| format!("{}: {e}", path.display());
    let mut f = AtomicFile::create(&path).map_err(fail)?;
    f.writer()
        .write_all(html(dir, title, summary, files).as_bytes())
        .map_err(fail)?;
    f.commit().map_err(fail)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_are_relative_and_text_is_escaped() {
        let dir = Path::new("/tmp/out");
        let files = [
            dir.join("run.csv"),
            dir.join("forces.svg"),
            PathBuf::from("/elsewhere/x<y>.svg"),
        ];
        let h = html(dir, "scene <a & b>", "max force 5 N < 12 N", &files);
        assert!(h.contains("<title>scene &lt;a &amp; b&gt;</title>"));
        assert!(h.contains("<pre>max force 5 N &lt; 12 N</pre>"));
        assert!(h.contains("<a href=\"run.csv\">run.csv</a>"));
        assert!(h.contains("<img src=\"forces.svg\""));
        assert!(h.contains("<img src=\"x&lt;y&gt;.svg\""));
        assert_eq!(
            h.matches("<img ").count(),
            2,
            "the CSV is a link, not an image"
        );
        assert!(!h.contains("/tmp/out"), "no absolute paths");
    }
}
