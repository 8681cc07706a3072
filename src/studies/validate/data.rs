//! The measurements the validation compares with (`--data DIR`, the repository's `data/` by
//! default): Taylor bars (`taylor.csv`), the Forrestal et al. (1994) shots (`forrestal1994.csv`)
//! and the CRH 3 rods (`crh3-rods.csv`). Each file names its columns in the last comment line
//! before the data.

use std::path::Path;

use super::ValidateError;

/// One Taylor impact test (Johnson & Cook 1983), SI units.
#[derive(Clone, Debug, PartialEq)]
pub struct TaylorTest {
    pub material: String,
    pub diameter: f64,
    pub length: f64,
    pub velocity: f64,
    pub final_length: f64,
    pub mushroom_diameter: f64,
}

/// One penetration shot, SI units.
#[derive(Clone, Debug, PartialEq)]
pub struct Shot {
    /// The set it belongs to; its scene is `cases/<set>-<velocity>.toml`.
    pub set: String,
    pub velocity: f64,
    /// Measured projectile mass (kg).
    pub mass: f64,
    /// Unconfined compressive strength (Pa).
    pub fc: f64,
    /// Measured depth of penetration (m).
    pub depth: f64,
    /// The projectile's outline where the file gives it per row (the Forrestal 1994 file gives
    /// one outline in its header).
    pub outline: Option<Outline>,
}

/// An ogive-nosed projectile's outline, SI units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline {
    pub diameter: f64,
    pub length: f64,
    pub crh: f64,
}

pub const TAYLOR_FILE: &str = "taylor.csv";
pub const FORRESTAL_FILE: &str = "forrestal1994.csv";
pub const CRH3_RODS_FILE: &str = "crh3-rods.csv";
/// The set name of the shots of [`FORRESTAL_FILE`].
pub const FORRESTAL_SET: &str = "forrestal1994";
/// The most bytes a data file may have: the shipped ones have under 1 kB.
const DATA_FILE_LIMIT: u64 = 16 << 20;

pub fn taylor(dir: &Path) -> Result<Vec<TaylorTest>, ValidateError> {
    let table = Table::read(&dir.join(TAYLOR_FILE))?;
    let mm = 1e-3;
    table.rows(|row| {
        Ok(TaylorTest {
            material: row.text("material")?,
            diameter: row.number("diameter_mm")? * mm,
            length: row.number("length_mm")? * mm,
            velocity: row.number("velocity_m_s")?,
            final_length: row.number("final_length_mm")? * mm,
            mushroom_diameter: row.number("mushroom_diameter_mm")? * mm,
        })
    })
}

pub fn forrestal(dir: &Path) -> Result<Vec<Shot>, ValidateError> {
    let table = Table::read(&dir.join(FORRESTAL_FILE))?;
    table.rows(|row| {
        Ok(Shot {
            set: FORRESTAL_SET.into(),
            velocity: row.number("velocity_m_s")?,
            mass: row.number("mass_kg")?,
            fc: row.number("fc_MPa")? * 1e6,
            depth: row.number("depth_m")?,
            outline: None,
        })
    })
}

pub fn crh3_rods(dir: &Path) -> Result<Vec<Shot>, ValidateError> {
    let table = Table::read(&dir.join(CRH3_RODS_FILE))?;
    let mm = 1e-3;
    table.rows(|row| {
        Ok(Shot {
            set: row.text("set")?,
            velocity: row.number("velocity_m_s")?,
            mass: row.number("mass_kg")?,
            fc: row.number("fc_MPa")? * 1e6,
            depth: row.number("depth_m")?,
            outline: Some(Outline {
                diameter: row.number("diameter_mm")? * mm,
                length: row.number("length_mm")? * mm,
                crh: row.number("crh")?,
            }),
        })
    })
}

/// A data file: its column names (from the last comment line before the data) and its rows.
struct Table {
    file: String,
    columns: Vec<String>,
    /// (line number, fields)
    rows: Vec<(usize, Vec<String>)>,
}

impl Table {
    fn read(path: &Path) -> Result<Table, ValidateError> {
        let file = path.display().to_string();
        let unreadable = |why: String| {
            ValidateError::Input(format!(
                "{file}: cannot read the data file ({why}); pass --data DIR, the folder with \
                 {TAYLOR_FILE}, {FORRESTAL_FILE} and {CRH3_RODS_FILE}"
            ))
        };
        let bytes = crate::scene::read_capped(path, DATA_FILE_LIMIT)
            .map_err(|e| unreadable(e.to_string()))?
            .ok_or_else(|| unreadable(format!("larger than {} MiB", DATA_FILE_LIMIT >> 20)))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            unreadable(format!(
                "not UTF-8 text, invalid byte at offset {}",
                e.utf8_error().valid_up_to()
            ))
        })?;
        // Line by line, so errors name the line: the csv crate's record positions leave out
        // the comment and blank lines it skips.
        let fields = |line: &str, number: usize| -> Result<Vec<String>, ValidateError> {
            let mut reader = csv::ReaderBuilder::new()
                .has_headers(false)
                .trim(csv::Trim::All)
                .from_reader(line.as_bytes());
            let mut record = csv::StringRecord::new();
            reader.read_record(&mut record).map_err(|e| {
                ValidateError::Input(format!("{file}:{number}: not a CSV row ({e})"))
            })?;
            Ok(record.iter().map(str::to_string).collect())
        };
        let mut columns = Vec::new();
        let mut rows = Vec::new();
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if let Some(comment) = line.strip_prefix('#') {
                if rows.is_empty() && comment.contains(',') {
                    columns = fields(comment, i + 1)?;
                }
            } else if !line.is_empty() {
                rows.push((i + 1, fields(line, i + 1)?));
            }
        }
        if columns.is_empty() || rows.is_empty() {
            return Err(ValidateError::Input(format!(
                "{file}: expected a `# column,names` comment line followed by data rows"
            )));
        }
        Ok(Table {
            file,
            columns,
            rows,
        })
    }

    fn rows<T>(
        &self,
        mut parse: impl FnMut(&Row) -> Result<T, ValidateError>,
    ) -> Result<Vec<T>, ValidateError> {
        self.rows
            .iter()
            .map(|(line, fields)| {
                parse(&Row {
                    table: self,
                    line: *line,
                    fields,
                })
            })
            .collect()
    }
}

struct Row<'a> {
    table: &'a Table,
    line: usize,
    fields: &'a [String],
}

impl Row<'_> {
    fn text(&self, column: &str) -> Result<String, ValidateError> {
        let t = self.table;
        let k = t.columns.iter().position(|c| c == column).ok_or_else(|| {
            ValidateError::Input(format!(
                "{}: no column `{column}` (columns: {})",
                t.file,
                t.columns.join(", ")
            ))
        })?;
        self.fields.get(k).cloned().ok_or_else(|| {
            ValidateError::Input(format!(
                "{}:{}: the row has no `{column}` field",
                t.file, self.line
            ))
        })
    }

    fn number(&self, column: &str) -> Result<f64, ValidateError> {
        let text = self.text(column)?;
        match text.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(ValidateError::Input(format!(
                "{}:{}: {column} = `{text}` is not a number",
                self.table.file, self.line
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A data path that never ends (/dev/zero) is refused at the limit, not read on.
    #[cfg(unix)]
    #[test]
    fn an_endless_data_file_is_refused() {
        let e = Table::read(Path::new("/dev/zero"))
            .err()
            .unwrap()
            .to_string();
        assert!(
            e.contains("/dev/zero") && e.contains("larger than 16 MiB"),
            "{e}"
        );
    }

    /// The shipped rods file: two sets, each row with its outline, in SI units.
    #[test]
    fn the_rods_file_gives_each_shot_its_set_and_outline() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
        let shots = crh3_rods(&dir).unwrap();
        assert_eq!(shots.len(), 6);
        let first = &shots[0];
        assert_eq!(first.set, "frew-30mm-58");
        assert_eq!(
            (first.velocity, first.mass, first.depth),
            (445.0, 1.62, 0.46)
        );
        assert!((first.fc - 58.4e6).abs() < 1.0);
        let o = first.outline.unwrap();
        assert!((o.diameter - 0.0305).abs() < 1e-12 && (o.length - 0.3048).abs() < 1e-12);
        assert_eq!(o.crh, 3.0);
        assert!(shots.iter().filter(|s| s.set == "f96-64g-13").count() == 3);
        assert!(forrestal(&dir).unwrap().iter().all(|s| s.outline.is_none()));
    }

    #[test]
    fn columns_come_from_the_comment_line_before_the_data() {
        let dir = std::env::temp_dir().join(format!("penetrate-data-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join(FORRESTAL_FILE),
            "# a comment, with a comma\n# depth_m,velocity_m_s,mass_kg,fc_MPa\n0.2,300,0.9,35\n",
        )
        .unwrap();
        let shots = forrestal(&dir).unwrap();
        assert_eq!(
            shots,
            vec![Shot {
                set: FORRESTAL_SET.into(),
                velocity: 300.0,
                mass: 0.9,
                fc: 35e6,
                depth: 0.2,
                outline: None,
            }]
        );
        std::fs::write(dir.join(FORRESTAL_FILE), "# velocity_m_s,mass_kg\nfast,1\n").unwrap();
        let e = forrestal(&dir).unwrap_err().to_string();
        assert!(
            e.contains("forrestal1994.csv:2: velocity_m_s = `fast`"),
            "{e}"
        );
        // A quoted field may hold a comma.
        std::fs::write(
            dir.join(TAYLOR_FILE),
            "# material,diameter_mm,length_mm,velocity_m_s,final_length_mm,mushroom_diameter_mm\n\
             \"steel, 4340\",1,2,3,4,5\n",
        )
        .unwrap();
        assert_eq!(taylor(&dir).unwrap()[0].material, "steel, 4340");
        std::fs::remove_file(dir.join(TAYLOR_FILE)).unwrap();
        let e = taylor(&dir).unwrap_err().to_string();
        assert!(
            e.contains("cannot read the data file") && e.contains("--data"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
