//! Self-contained HTML pages: every figure is embedded as a `data:` URI and the style is inline,
//! so a report opens from a file, offline, with nothing beside it. No script runs.
//!
//! [`Html`] builds a fragment (escaped text, tables, figures); [`Html::page`] wraps it into a
//! whole document. The fragment alone, under its `wj-report` class, is what a notebook shows.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use base64::Engine as _;

use crate::files::{AtomicFile, OutputError, io_err, write_atomic};

/// The page's style, scoped under `.wj-report` so a fragment embedded in a notebook leaves the
/// notebook's own style alone.
const STYLE: &str = "\
.wj-report{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;color:#1d2430;\
max-width:1180px;margin:0 auto;padding:0 16px 40px;line-height:1.45}\
.wj-report h1{font-size:1.5em;margin:.8em 0 .2em}\
.wj-report h2{font-size:1.2em;margin:1.4em 0 .4em;border-bottom:1px solid #d5dae1}\
.wj-report h3{font-size:1.05em;margin:1em 0 .3em}\
.wj-report table{border-collapse:collapse;margin:.4em 0 1em;font-size:.92em}\
.wj-report th,.wj-report td{border:1px solid #d5dae1;padding:3px 8px;text-align:left;\
vertical-align:top}\
.wj-report th{background:#f1f3f6}\
.wj-report td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
.wj-report .ok{color:#176b2c;font-weight:600}\
.wj-report .bad{color:#a4161a;font-weight:600}\
.wj-report .warn{background:#fff4d6;border-left:4px solid #e0a800;padding:6px 10px;margin:.6em 0}\
.wj-report .lede{color:#4a5568}\
.wj-report figure{margin:1em 0 1.6em;display:inline-block;vertical-align:top;max-width:100%}\
.wj-report figure img{max-width:100%;height:auto;border:1px solid #e2e6ea}\
.wj-report figcaption{font-size:.9em;color:#4a5568;max-width:900px}\
.wj-report code{background:#f1f3f6;padding:0 3px;border-radius:3px}";

/// An HTML fragment being built; text handed to it is escaped unless a method says otherwise.
#[derive(Debug, Default, Clone)]
pub struct Html {
    body: String,
}

/// A cell of [`Html::table`].
#[derive(Debug, Clone)]
pub enum Td {
    /// Text, left-aligned.
    Text(String),
    /// A number already formatted with its unit, right-aligned.
    Num(String),
    /// A verdict: green when `true`, red when `false`.
    Verdict(String, bool),
}

impl Td {
    /// A text cell.
    pub fn text(s: impl Into<String>) -> Self {
        Td::Text(s.into())
    }
    /// A number cell.
    pub fn num(s: impl Into<String>) -> Self {
        Td::Num(s.into())
    }
}

/// `text` with `&`, `<`, `>` and quotes escaped.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// The MIME type of an image file from its extension (`None`: not an image a page shows).
pub fn image_mime(path: &Path) -> Option<&'static str> {
    match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
        "png" => Some("image/png"),
        "gif" => Some("image/gif"),
        "svg" => Some("image/svg+xml"),
        "jpg" | "jpeg" => Some("image/jpeg"),
        _ => None,
    }
}

/// Whether a link target is a plain relative path (not a URL, not absolute, no `..`).
fn is_relative_file(target: &str) -> bool {
    !target.contains(':')
        && !target.starts_with('/')
        && Path::new(target)
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
}

/// Writes `md` to `<dir>/<stem>.md` and the same as a self-contained page, `<dir>/<stem>.html`
/// (images embedded); returns the markdown file's path.
pub fn write_markdown_and_page(
    dir: &Path,
    stem: &str,
    md: &str,
    title: &str,
) -> Result<std::path::PathBuf, OutputError> {
    let path = dir.join(format!("{stem}.md"));
    write_atomic(&path, md.as_bytes())?;
    let mut html = Html::new();
    html.markdown(md, dir)?;
    html.write_page(&dir.join(format!("{stem}.html")), title)?;
    Ok(path)
}

/// `bytes` as a `data:` URI of type `mime`.
pub fn data_uri(mime: &str, bytes: &[u8]) -> String {
    format!(
        "data:{mime};base64,{}",
        base64::engine::general_purpose::STANDARD.encode(bytes)
    )
}

impl Html {
    /// An empty fragment.
    pub fn new() -> Self {
        Self::default()
    }

    /// A heading of `level` (1–3).
    pub fn heading(&mut self, level: u8, text: &str) -> &mut Self {
        let level = level.clamp(1, 3);
        let _ = writeln!(self.body, "<h{level}>{}</h{level}>", escape(text));
        self
    }

    /// A paragraph of plain text.
    pub fn paragraph(&mut self, text: &str) -> &mut Self {
        let _ = writeln!(self.body, "<p>{}</p>", escape(text));
        self
    }

    /// A paragraph in the muted style that introduces a section.
    pub fn lede(&mut self, text: &str) -> &mut Self {
        let _ = writeln!(self.body, "<p class=\"lede\">{}</p>", escape(text));
        self
    }

    /// A highlighted warning.
    pub fn warning(&mut self, text: &str) -> &mut Self {
        let _ = writeln!(self.body, "<div class=\"warn\">{}</div>", escape(text));
        self
    }

    /// A bulleted list of plain-text items.
    pub fn list<S: AsRef<str>>(&mut self, items: &[S]) -> &mut Self {
        self.body.push_str("<ul>\n");
        for item in items {
            let _ = writeln!(self.body, "<li>{}</li>", escape(item.as_ref()));
        }
        self.body.push_str("</ul>\n");
        self
    }

    /// A link to a file beside the page (`href` relative), e.g. a scene's own report.
    pub fn link(&mut self, href: &str, text: &str) -> &mut Self {
        let _ = writeln!(
            self.body,
            "<p><a href=\"{}\">{}</a></p>",
            escape(href),
            escape(text)
        );
        self
    }

    /// Markup that is already HTML (a renderer's output).
    pub fn raw(&mut self, html: &str) -> &mut Self {
        self.body.push_str(html);
        self
    }

    /// A table with a header row; every row must have as many cells as `header`.
    pub fn table<S: AsRef<str>>(&mut self, header: &[S], rows: &[Vec<Td>]) -> &mut Self {
        self.body.push_str("<table>\n<tr>");
        for h in header {
            let _ = write!(self.body, "<th>{}</th>", escape(h.as_ref()));
        }
        self.body.push_str("</tr>\n");
        for row in rows {
            self.body.push_str("<tr>");
            for cell in row {
                match cell {
                    Td::Text(t) => {
                        let _ = write!(self.body, "<td>{}</td>", escape(t));
                    }
                    Td::Num(t) => {
                        let _ = write!(self.body, "<td class=\"num\">{}</td>", escape(t));
                    }
                    Td::Verdict(t, good) => {
                        let class = if *good { "ok" } else { "bad" };
                        let _ = write!(self.body, "<td class=\"{class}\">{}</td>", escape(t));
                    }
                }
            }
            self.body.push_str("</tr>\n");
        }
        self.body.push_str("</table>\n");
        self
    }

    /// The image file `path` embedded in the page with `caption`; `alt` names it for readers
    /// who cannot see it.
    pub fn figure(
        &mut self,
        path: &Path,
        alt: &str,
        caption: &str,
    ) -> Result<&mut Self, OutputError> {
        let mime = image_mime(path).ok_or_else(|| {
            io_err(path)(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not an image file a page can embed",
            ))
        })?;
        let bytes = std::fs::read(path).map_err(io_err(path))?;
        let _ = writeln!(
            self.body,
            "<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>",
            data_uri(mime, &bytes),
            escape(alt),
            escape(caption)
        );
        Ok(self)
    }

    /// Markdown rendered as HTML (tables included); the images it shows that are files in `dir`
    /// (relative paths) are embedded, links are kept as they are.
    pub fn markdown(&mut self, md: &str, dir: &Path) -> Result<&mut Self, OutputError> {
        use pulldown_cmark::{CowStr, Event, Options, Parser, Tag};
        let mut events = Vec::new();
        for event in Parser::new_ext(md, Options::ENABLE_TABLES) {
            events.push(match event {
                Event::Start(Tag::Image {
                    link_type,
                    dest_url,
                    title,
                    id,
                }) => {
                    let path = dir.join(dest_url.as_ref());
                    let embedded = match image_mime(&path) {
                        Some(mime) if is_relative_file(&dest_url) => {
                            let bytes = std::fs::read(&path).map_err(io_err(&path))?;
                            CowStr::from(data_uri(mime, &bytes))
                        }
                        _ => dest_url,
                    };
                    Event::Start(Tag::Image {
                        link_type,
                        dest_url: embedded,
                        title,
                        id,
                    })
                }
                other => other,
            });
        }
        pulldown_cmark::html::push_html(&mut self.body, events.into_iter());
        Ok(self)
    }

    /// The fragment, wrapped in its scoped style (what a notebook shows).
    pub fn fragment(&self) -> String {
        let mut out = Vec::with_capacity(self.body.len() + STYLE.len() + 64);
        // Writing into memory cannot fail, and every piece is UTF-8.
        let _ = self.write_fragment(&mut out);
        String::from_utf8_lossy(&out).into_owned()
    }

    /// A whole document titled `title` around the fragment.
    pub fn page(&self, title: &str) -> String {
        let mut out = Vec::with_capacity(self.body.len() + STYLE.len() + 512);
        let _ = self.write_document(title, &mut out);
        String::from_utf8_lossy(&out).into_owned()
    }

    /// Writes the document titled `title` to `path` atomically, streamed: a page with its
    /// figures embedded is megabytes, and is not copied on the way.
    pub fn write_page(&self, path: &Path, title: &str) -> Result<(), OutputError> {
        let mut file = AtomicFile::create(path)?;
        self.write_document(title, &mut file)
            .map_err(io_err(path))?;
        file.commit().map(drop)
    }

    fn write_fragment(&self, w: &mut impl Write) -> std::io::Result<()> {
        write!(w, "<div class=\"wj-report\">\n<style>{STYLE}</style>\n")?;
        w.write_all(self.body.as_bytes())?;
        w.write_all(b"</div>\n")
    }

    fn write_document(&self, title: &str, w: &mut impl Write) -> std::io::Result<()> {
        write!(
            w,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <title>{}</title>\n</head>\n<body>\n",
            escape(title)
        )?;
        self.write_fragment(w)?;
        w.write_all(b"</body>\n</html>\n")
    }
}
