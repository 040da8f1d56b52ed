//! Tree lists: the scenario's CSV (`x_m,y_m,dbh_cm[,species][,height_m]`) and the Rockyfor3D
//! tree file (`treefile.txt`: x, y, DBH in cm, optional conifer flag or species).

use crate::InputError;
use rockfall_forest::{Species, Stem, height_from_dbh_m};
use std::path::Path;

/// Reads a tree CSV. With a header row, columns are found by name (`x_m`, `y_m`, `dbh_cm`,
/// optional `species`, optional `height_m`; other names are errors); without one, they are
/// taken in that order. `species` is a species name or code, `conifer`/`broadleaf`, or a
/// conifer flag 1/0. A missing height comes from the DBH allometry.
pub fn read_tree_csv(path: &Path) -> Result<Vec<Stem>, InputError> {
    Ok(read_tree_list(path, TreeFormat::Csv, |_| true)?.0)
}

/// [`read_tree_csv`] on a text already read; `path` names the source in errors.
pub fn parse_tree_csv(text: &str, path: &Path) -> Result<Vec<Stem>, InputError> {
    parse_list(text, path, TreeFormat::Csv)
}

/// Reads a Rockyfor3D tree file: whitespace-, tab-, comma- or semicolon-separated columns
/// x (m), y (m), DBH (cm) and optionally a fourth column read as a conifer flag (1 conifer,
/// 0 broadleaf) or a species name. A first line that does not start with a number is a
/// header and skipped. Heights come from the DBH allometry.
pub fn read_treefile(path: &Path) -> Result<Vec<Stem>, InputError> {
    Ok(read_tree_list(path, TreeFormat::Treefile, |_| true)?.0)
}

/// [`read_treefile`] on a text already read; `path` names the source in errors.
pub fn parse_treefile(text: &str, path: &Path) -> Result<Vec<Stem>, InputError> {
    parse_list(text, path, TreeFormat::Treefile)
}

/// The two tree-list formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TreeFormat {
    /// The scenario's CSV ([`read_tree_csv`]).
    Csv,
    /// Rockyfor3D's tree file ([`read_treefile`]).
    Treefile,
}

/// Reads a tree list line by line, keeping the stems `keep` accepts (a tile keeps those in its
/// window): every row is still checked, but only the kept stems are held, so a national list
/// need not fit in memory. Returns the kept stems, in the file's order, and the number of
/// trees the list holds. A list without a tree is an error.
pub fn read_tree_list(
    path: &Path,
    format: TreeFormat,
    keep: impl Fn(&Stem) -> bool,
) -> Result<(Vec<Stem>, usize), InputError> {
    use std::io::BufRead;
    let file = std::fs::File::open(path).map_err(|e| InputError::io(path, e))?;
    let mut rows = Rows::new(format, path);
    let mut kept = Vec::new();
    for (i, line) in std::io::BufReader::new(file).lines().enumerate() {
        let line = line.map_err(|e| InputError::io(path, e))?;
        if let Some(stem) = rows.row(i + 1, &line)?.filter(&keep) {
            kept.push(stem);
        }
    }
    Ok((kept, rows.finish()?))
}

fn parse_list(text: &str, path: &Path, format: TreeFormat) -> Result<Vec<Stem>, InputError> {
    let mut rows = Rows::new(format, path);
    let mut stems = Vec::new();
    for (i, line) in text.lines().enumerate() {
        stems.extend(rows.row(i + 1, line)?);
    }
    rows.finish()?;
    Ok(stems)
}

/// A tree list's rows, one line at a time: the header (if any) decided on the first row, then
/// a stem per row.
struct Rows<'p> {
    format: TreeFormat,
    path: &'p Path,
    /// The columns, once the first row has been seen.
    cols: Option<Columns>,
    trees: usize,
}

impl<'p> Rows<'p> {
    fn new(format: TreeFormat, path: &'p Path) -> Self {
        Rows {
            format,
            path,
            cols: None,
            trees: 0,
        }
    }

    /// The stem of line `line` (1-based), `None` for a blank, comment (`#`) or header line.
    fn row(&mut self, line: usize, text: &str) -> Result<Option<Stem>, InputError> {
        // a leading byte-order mark, which spreadsheets write, is dropped
        let text = match line {
            1 => text.strip_prefix('\u{feff}').unwrap_or(text),
            _ => text,
        };
        if text.trim().is_empty() || text.trim_start().starts_with('#') {
            return Ok(None);
        }
        let fields: Vec<&str> = match self.format {
            TreeFormat::Csv => text.split(',').map(str::trim).collect(),
            TreeFormat::Treefile => text
                .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
                .filter(|t| !t.is_empty())
                .collect(),
        };
        let cols = match &self.cols {
            Some(c) => c,
            None => {
                let header = fields.first().is_some_and(|t| t.parse::<f64>().is_err());
                let cols = match (header, self.format) {
                    (true, TreeFormat::Csv) => Columns::from_header(&fields, self.path, line)?,
                    _ => Columns::positional(),
                };
                let cols = self.cols.insert(cols);
                if header {
                    return Ok(None);
                }
                cols
            }
        };
        if self.format == TreeFormat::Treefile && fields.len() > 4 {
            return Err(row_err(
                self.path,
                line,
                format!("expected 3 or 4 columns, found {}", fields.len()),
            ));
        }
        let stem = cols.stem(&fields, self.path, line)?;
        self.trees += 1;
        Ok(Some(stem))
    }

    /// The number of trees read; an error when there is none.
    fn finish(self) -> Result<usize, InputError> {
        let what = match self.format {
            TreeFormat::Csv => "the tree list holds no tree",
            TreeFormat::Treefile => "the tree file holds no tree",
        };
        match self.trees {
            0 => Err(InputError::invalid(self.path, what)),
            n => Ok(n),
        }
    }
}

/// Writes stems as a tree CSV with header `x_m,y_m,dbh_cm,species,height_m`, atomically.
pub fn write_tree_csv(path: &Path, stems: &[Stem]) -> Result<(), InputError> {
    let mut s = String::from("x_m,y_m,dbh_cm,species,height_m\n");
    for t in stems {
        s += &format!(
            "{},{},{},{},{}\n",
            t.x_m,
            t.y_m,
            t.dbh_cm,
            t.species.name(),
            t.height_m
        );
    }
    crate::write_text(path, &s)
}

/// Writes stems as a Rockyfor3D tree file (`x y dbh_cm conifer_flag`, header line), atomically.
pub fn write_treefile(path: &Path, stems: &[Stem]) -> Result<(), InputError> {
    let mut s = String::from("x\ty\tdbh_cm\tconifer\n");
    for t in stems {
        let flag = u8::from(t.species.is_conifer().unwrap_or(true));
        s += &format!("{}\t{}\t{}\t{flag}\n", t.x_m, t.y_m, t.dbh_cm);
    }
    crate::write_text(path, &s)
}

fn row_err(path: &Path, line: usize, message: String) -> InputError {
    InputError::Trees {
        path: path.to_path_buf(),
        line,
        message,
    }
}

/// Column positions of x, y, dbh, species, height.
struct Columns {
    x: usize,
    y: usize,
    dbh: usize,
    species: Option<usize>,
    height: Option<usize>,
    /// Without a header the 4th and 5th columns are optional.
    positional: bool,
}

impl Columns {
    fn positional() -> Self {
        Columns {
            x: 0,
            y: 1,
            dbh: 2,
            species: Some(3),
            height: Some(4),
            positional: true,
        }
    }

    fn from_header(names: &[&str], path: &Path, line: usize) -> Result<Self, InputError> {
        let find = |n: &str| names.iter().position(|h| h.eq_ignore_ascii_case(n));
        for h in names {
            let known = ["x_m", "y_m", "dbh_cm", "species", "height_m"];
            if !known.iter().any(|k| h.eq_ignore_ascii_case(k)) {
                return Err(row_err(
                    path,
                    line,
                    format!("unknown column `{h}` (expected x_m, y_m, dbh_cm, species, height_m)"),
                ));
            }
        }
        let need =
            |n: &str| find(n).ok_or_else(|| row_err(path, line, format!("missing column `{n}`")));
        Ok(Columns {
            x: need("x_m")?,
            y: need("y_m")?,
            dbh: need("dbh_cm")?,
            species: find("species"),
            height: find("height_m"),
            positional: false,
        })
    }

    fn stem(&self, f: &[&str], path: &Path, line: usize) -> Result<Stem, InputError> {
        let width = if self.positional {
            3
        } else {
            [self.x, self.y, self.dbh]
                .into_iter()
                .chain(self.species)
                .chain(self.height)
                .max()
                .unwrap_or(0)
                + 1
        };
        if f.len() < width || (self.positional && f.len() > 5) {
            return Err(row_err(
                path,
                line,
                format!("expected {width} columns, found {}", f.len()),
            ));
        }
        let num = |i: usize, what: &str| -> Result<f64, InputError> {
            let t = f[i];
            match t.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(row_err(
                    path,
                    line,
                    format!("{what} `{t}` is not a finite number"),
                )),
            }
        };
        let x_m = num(self.x, "x")?;
        let y_m = num(self.y, "y")?;
        let dbh_cm = num(self.dbh, "DBH")?;
        let species = (self.species.and_then(|i| f.get(i).copied())).filter(|t| !t.is_empty());
        let height_m = match self
            .height
            .filter(|&i| f.get(i).is_some_and(|t| !t.is_empty()))
        {
            Some(i) => Some(num(i, "height")?),
            None => None,
        };
        make_stem(x_m, y_m, dbh_cm, species, height_m).map_err(|m| row_err(path, line, m))
    }
}

/// A stem from a tree list's values, checked: DBH positive, a known species (a name or code,
/// `conifer`/`broadleaf`, or a conifer flag 1/0; none is unknown), a height above breast
/// height (none: from the DBH allometry). Shared by tree lists and tree point layers.
pub(crate) fn make_stem(
    x_m: f64,
    y_m: f64,
    dbh_cm: f64,
    species: Option<&str>,
    height_m: Option<f64>,
) -> Result<Stem, String> {
    if dbh_cm.is_nan() || dbh_cm <= 0.0 {
        return Err(format!("DBH must be positive, found {dbh_cm} cm"));
    }
    let species = match species {
        None => Species::Unknown,
        Some("1") => Species::OtherConifer,
        Some("0") => Species::OtherBroadleaf,
        Some(t) => Species::parse(t).ok_or_else(|| format!("unknown species `{t}`"))?,
    };
    let height_m = match height_m {
        Some(h) if h.is_nan() || h <= 1.3 => {
            return Err(format!(
                "height must exceed breast height 1.3 m, found {h} m"
            ));
        }
        Some(h) => h,
        None => height_from_dbh_m(dbh_cm),
    };
    Ok(Stem {
        x_m,
        y_m,
        dbh_cm,
        height_m,
        species,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(text: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("trees.csv");
        std::fs::write(&p, text).unwrap();
        (dir, p)
    }

    #[test]
    fn blank_and_comment_lines_column_counts_and_empty_lists() {
        let p = Path::new("trees.csv");
        let n = |r: Result<Vec<Stem>, InputError>| r.map(|s| s.len()).map_err(|e| e.to_string());
        // an indented comment and a line of spaces are skipped, before and after the header
        assert_eq!(
            n(parse_tree_csv(
                "  # note\nx_m,y_m,dbh_cm\n  # more\n1,1,30\n   \n",
                p
            )),
            Ok(1)
        );
        assert_eq!(
            n(parse_treefile("  \n\t# trees\n1 1 30\n \t \n2 2 35\n", p)),
            Ok(2)
        );
        // a tree file row of 5 columns names its line
        let e = n(parse_treefile("x y dbh\n1 2 30 1\n1 2 30 1 25\n", p)).unwrap_err();
        assert!(
            e.contains("line 3") && e.contains("expected 3 or 4 columns, found 5"),
            "{e}"
        );
        // a header alone, comments alone: no tree
        for (csv, text) in [
            (true, "x_m,y_m,dbh_cm\n"),
            (false, "x y dbh\n"),
            (true, "# x\n\n"),
        ] {
            let r = match csv {
                true => parse_tree_csv(text, p),
                false => parse_treefile(text, p),
            };
            let e = n(r).unwrap_err();
            assert!(e.contains("holds no tree"), "{text:?}: {e}");
        }
    }

    #[test]
    fn csv_with_header_in_any_order_and_without() {
        let (_d, p) = file("dbh_cm,x_m,y_m,species\n30,1,2,Abies alba\n45.5,3,4,\n");
        let s = read_tree_csv(&p).unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!((s[0].x_m, s[0].y_m, s[0].dbh_cm), (1.0, 2.0, 30.0));
        assert_eq!(s[0].species, Species::AbiesAlba);
        assert_eq!(s[1].species, Species::Unknown);
        assert!((s[1].height_m - height_from_dbh_m(45.5)).abs() < 1e-12);
        let (_d, p) = file("1,2,30,piab,25\n3,4,20\n");
        let s = read_tree_csv(&p).unwrap();
        assert_eq!(s[0].species, Species::PiceaAbies);
        assert_eq!(s[0].height_m, 25.0);
    }

    #[test]
    fn bad_rows_name_file_and_line() {
        for (text, needle) in [
            ("x_m,y_m,dbh_cm\n1,2,-30\n", "line 2: DBH must be positive"),
            ("x_m,y_m,dbh_cm\n1,2,30\n1,nan,30\n", "line 3: y `nan`"),
            ("x_m,y_m,dbh_cm,colour\n", "unknown column `colour`"),
            ("x_m,dbh_cm\n", "missing column `y_m`"),
            ("1,2\n", "line 1: expected 3 columns"),
            ("1,2,30,oak-ish\n", "unknown species"),
            ("1,2,30,beech,1.0\n", "breast height"),
            ("x_m,y_m,dbh_cm\n", "no tree"),
        ] {
            let (_d, p) = file(text);
            let e = read_tree_csv(&p).unwrap_err().to_string();
            assert!(
                e.contains("trees.csv") && e.contains(needle),
                "{text:?} → {e}"
            );
        }
    }

    #[test]
    fn rockyfor_treefile_round_trip() {
        let (_d, p) = file("x y dbh\n10.5\t20 31\n11 21 40 0\n");
        let s = read_treefile(&p).unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[1].species, Species::OtherBroadleaf);
        let out = p.with_file_name("treefile.txt");
        write_treefile(&out, &s).unwrap();
        let back = read_treefile(&out).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!((back[0].x_m, back[0].dbh_cm), (10.5, 31.0));
        let (_d, p) = file("x y dbh\n");
        // a non-numeric first line is a header; the file then holds no tree
        assert!(
            read_treefile(&p)
                .unwrap_err()
                .to_string()
                .contains("no tree")
        );
        let (_d, p) = file("1 2 3\n1 2 x\n");
        assert!(
            read_treefile(&p)
                .unwrap_err()
                .to_string()
                .contains("line 2")
        );
    }
}
