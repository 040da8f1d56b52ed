//! `rockfall schema`: the scenario file's JSON Schema, or its Markdown key reference, on
//! standard output or written to a file.

use crate::Failure;
use anyhow::anyhow;
use std::io::Write;
use std::path::Path;

/// Prints the schema (or with `markdown` the key reference), or writes it to `out`
/// atomically. A file that cannot be written is bad input (exit 2), named.
pub fn schema(markdown: bool, out: Option<&Path>) -> Result<(), Failure> {
    let text = if markdown {
        rockfall_io::schema_doc::reference_markdown()
    } else {
        rockfall_io::schema_doc::schema_json()
    };
    match out {
        Some(path) => {
            if path.is_dir() {
                return Err(Failure::BadInput(anyhow!(
                    "{}: is a folder; --out names the file to write",
                    path.display()
                )));
            }
            rockfall_raster::atomic::write_bytes_atomic(path, text.as_bytes()).map_err(
                |(p, e)| Failure::BadInput(anyhow!("{}: cannot write: {e}", p.display())),
            )?;
            println!("wrote {}", path.display());
            Ok(())
        }
        None => {
            let mut stdout = std::io::stdout().lock();
            match stdout.write_all(text.as_bytes()) {
                // a reader that closed our stdout early (`rockfall schema | head`) is not a
                // failure
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(Failure::Internal(
                    anyhow!("writing to standard output: {e}"),
                )),
                _ => Ok(()),
            }
        }
    }
}
