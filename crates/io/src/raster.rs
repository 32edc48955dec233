//! Raster layouts the instrument readers share.

/// The samples of a raster of `nx` samples a line, `width` bytes each,
/// stored from the image's last line (as Nanoscope, Nanosurf, MI, Park and
/// FRT files store it), in asperity's order: line 0 first, x fastest.
pub(crate) fn from_last_line(data: &[u8], nx: usize, width: usize) -> impl Iterator<Item = &[u8]> {
    data.chunks_exact(nx * width)
        .rev()
        .flat_map(move |line| line.chunks_exact(width))
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_last_stored_line_comes_first() {
        let data = [1u8, 2, 3, 4, 5, 6];
        let order: Vec<u8> = super::from_last_line(&data, 3, 1).map(|s| s[0]).collect();
        assert_eq!(order, [4, 5, 6, 1, 2, 3]);
    }
}
