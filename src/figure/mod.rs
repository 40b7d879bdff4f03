//! The fonts the binary carries: DejaVu Sans, committed under
//! `assets/fonts`, the window's fallback for glyphs egui's own fonts lack.
//! Pictures for files are drawn by the window's figure code
//! (`app::figure`; `oneblock figure`, `oneblock phase --png`).
//!
//! Nothing here depends on the `gui` feature.

/// DejaVu Sans (assets/fonts/README.md: its origin and licence); the
/// window's fallback for glyphs egui's own fonts lack (→ in "P2 → P1").
pub const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

#[cfg(test)]
mod tests {
    /// The committed font loads as DejaVu Sans.
    #[test]
    fn the_committed_font_is_dejavu_sans() {
        let mut db = resvg::usvg::fontdb::Database::new();
        db.load_font_data(super::FONT.to_vec());
        let names: Vec<String> = db
            .faces()
            .flat_map(|f| f.families.iter().map(|(n, _)| n.clone()))
            .collect();
        assert!(names.iter().any(|n| n == "DejaVu Sans"), "{names:?}");
    }
}
