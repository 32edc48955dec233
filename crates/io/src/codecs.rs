//! How the file of each format that holds a height field is decoded: one row
//! per format — its reader (of a chosen channel where it has several), its
//! channels, the instrument's metadata, and what its header declares it
//! decodes to — in one table that `read`, `channels`, `instrument_metadata`
//! and the memory estimate look up (they were one `match` over the formats
//! each). A new height-field format adds its module and its row here.

use asperity_core::HeightField;

use crate::channel::{Channel, ChannelInfo};
use crate::error::FResult;
use crate::{Format, Metadata};
use crate::{
    al3d, asc, bcr, datx, di, exr_io, frt, gsf, gwy, h5, hgt, ibw, jpk, lext, mat, mdt, metropro,
    mi, mitutoyo, mnt, nc, nid, nmm, nms, npy, npz, oir, opd, opdx, os3d, park, plu, plux, png_io,
    qep, sdf, sur, text, tmd, vk, wsxm, x3p, xz, zmg, zon,
};

/// Reads the height field of the channel chosen (None: the default one).
type Height = fn(&[u8], Option<&Channel>) -> FResult<HeightField>;
/// Lists a file's channels.
type Channels = fn(&[u8]) -> FResult<Vec<ChannelInfo>>;
/// Reads the instrument's metadata.
type Meta = fn(&[u8]) -> FResult<Metadata>;
/// The bytes a file declares it decodes to (before decoding anything).
type Declared = fn(&[u8]) -> FResult<u128>;

/// One format's decoding.
pub(crate) struct Codec {
    pub(crate) format: Format,
    pub(crate) height: Height,
    /// Set for the formats whose files hold several channels.
    pub(crate) channels: Option<Channels>,
    pub(crate) metadata: Option<Meta>,
    /// Set for the compressed containers whose memory estimate is what
    /// they declare rather than a multiple of the file's size.
    pub(crate) declared: Option<Declared>,
}

impl Codec {
    const fn new(format: Format, height: Height) -> Self {
        Self {
            format,
            height,
            channels: None,
            metadata: None,
            declared: None,
        }
    }
    const fn channels(mut self, c: Channels) -> Self {
        self.channels = Some(c);
        self
    }
    const fn metadata(mut self, m: Meta) -> Self {
        self.metadata = Some(m);
        self
    }
    const fn declared(mut self, d: Declared) -> Self {
        self.declared = Some(d);
        self
    }
}

/// The row of `format`, if it holds a height field.
pub(crate) fn of(format: Format) -> Option<&'static Codec> {
    CODECS.iter().find(|c| c.format == format)
}

/// Twice the inflated members of a zip-based format (each member inflated,
/// then parsed or converted).
fn zipped_twice(bytes: &[u8]) -> FResult<u128> {
    crate::zipped::declared_bytes(bytes).map(|n| n.saturating_mul(2))
}

/// A `.datx` under another name is read as one (SurfaceTopography too tries
/// DATX first).
fn read_h5(bytes: &[u8], choice: Option<&Channel>) -> FResult<HeightField> {
    if choice.is_none() && datx::sniff(bytes) {
        datx::read_height(bytes)
    } else {
        h5::read_channel(bytes, choice)
    }
}

fn h5_metadata(bytes: &[u8]) -> FResult<Metadata> {
    if datx::sniff(bytes) {
        datx::metadata(bytes)
    } else {
        Ok(Metadata::new())
    }
}

/// Every format that holds a height field.
const CODECS: &[Codec] = &[
    Codec::new(Format::Npy, |b, _| crate::npy_height(npy::read(b)?)),
    Codec::new(Format::Png, |b, _| png_io::read_height(b)),
    Codec::new(Format::Exr, |b, _| exr_io::read_height(b)),
    Codec::new(Format::Gsf, |b, _| gsf::read_height(b)),
    Codec::new(Format::Csv, |b, _| text::read_csv(b)),
    Codec::new(Format::Gwy, |b, _| gwy::read_height(b)),
    Codec::new(Format::X3p, |b, _| x3p::read_height(b))
        .declared(|b| x3p::header_pixels(b).map(crate::pixel_bytes)),
    Codec::new(Format::Sdf, |b, _| sdf::read_height(b)),
    Codec::new(Format::Sur, |b, _| sur::read_height(b)),
    Codec::new(Format::Tmd, |b, _| tmd::read_height(b)),
    Codec::new(Format::Bcr, |b, _| bcr::read_height(b)),
    Codec::new(Format::MetroPro, |b, _| metropro::read_height(b)),
    Codec::new(Format::Al3d, |b, _| al3d::read_height(b)),
    Codec::new(Format::Wsxm, |b, _| wsxm::read_height(b)),
    Codec::new(Format::Plu, plu::read_channel).channels(plu::channels),
    Codec::new(Format::Opd, |b, _| opd::read_height(b)),
    Codec::new(Format::Frt, |b, _| frt::read_height(b)),
    Codec::new(Format::Di, di::read_channel)
        .channels(di::channels)
        .metadata(di::metadata),
    Codec::new(Format::Nc, |b, _| nc::read_height(b)),
    Codec::new(Format::Nid, nid::read_channel)
        .channels(nid::channels)
        .metadata(nid::metadata),
    Codec::new(Format::Mi, mi::read_channel)
        .channels(mi::channels)
        .metadata(mi::metadata),
    Codec::new(Format::Ibw, ibw::read_channel)
        .channels(ibw::channels)
        .metadata(ibw::metadata),
    Codec::new(Format::Park, |b, _| park::read_height(b)),
    Codec::new(Format::Hfm, |b, _| xz::read_hfm(b)),
    Codec::new(Format::Dektak, |b, _| xz::read_dektak(b)),
    Codec::new(Format::CsvLineScan, |b, _| xz::read_titled_csv(b)),
    Codec::new(Format::Opdx, |b, _| opdx::read_height(b)),
    Codec::new(Format::Nms, |b, _| nms::read_height(b)).metadata(nms::metadata),
    Codec::new(Format::Mat, mat::read_channel)
        .channels(mat::channels)
        .declared(|b| mat::declared_points(b).map(crate::pixel_bytes)),
    Codec::new(Format::Npz, npz::read_channel)
        .channels(npz::channels)
        .declared(zipped_twice),
    Codec::new(Format::Hgt, |b, _| hgt::read_height(b)).metadata(hgt::metadata),
    Codec::new(Format::Vk, vk::read_channel)
        .channels(vk::channels)
        .metadata(vk::metadata)
        .declared(|b| vk::declared_points(b).map(crate::pixel_bytes)),
    Codec::new(Format::Mdt, mdt::read_channel).channels(mdt::channels),
    Codec::new(Format::Os3d, |b, _| os3d::read_height(b)).metadata(os3d::metadata),
    Codec::new(Format::Zmg, |b, _| zmg::read_height(b)).metadata(zmg::metadata),
    Codec::new(Format::Plux, plux::read_channel)
        .channels(plux::channels)
        .metadata(plux::metadata)
        .declared(zipped_twice),
    Codec::new(Format::Zon, |b, _| zon::read_height(b))
        .metadata(zon::metadata)
        .declared(|b| zon::declared_points(b).map(crate::pixel_bytes)),
    Codec::new(Format::Lext, |b, _| lext::read_height(b)).metadata(lext::metadata),
    Codec::new(Format::Jpk, jpk::read_channel).channels(jpk::channels),
    Codec::new(Format::Qep, qep::read_channel)
        .channels(qep::channels)
        .metadata(qep::metadata)
        .declared(zipped_twice),
    Codec::new(Format::Nmm, nmm::read_channel)
        .channels(nmm::channels)
        .metadata(nmm::metadata)
        .declared(zipped_twice),
    Codec::new(Format::Mnt, mnt::read_channel)
        .channels(mnt::channels)
        .metadata(mnt::metadata)
        .declared(|b| mnt::declared_points(b).map(crate::pixel_bytes)),
    Codec::new(Format::Asc, |b, _| asc::read_height(b)).metadata(asc::metadata),
    Codec::new(Format::Mitutoyo, |b, _| mitutoyo::read_height(b))
        .metadata(mitutoyo::metadata)
        .declared(zipped_twice),
    Codec::new(Format::H5, read_h5)
        .channels(h5::channels)
        .metadata(h5_metadata)
        .declared(|b| h5::declared_points(b).map(crate::pixel_bytes)),
    Codec::new(Format::Datx, |b, _| datx::read_height(b))
        .metadata(datx::metadata)
        .declared(|b| datx::declared_points(b).map(crate::pixel_bytes)),
    Codec::new(Format::Oir, oir::read_channel)
        .channels(oir::channels)
        .metadata(oir::metadata),
    Codec::new(Format::Poir, oir::read_packed)
        .channels(oir::packed_channels)
        .metadata(oir::packed_metadata)
        .declared(zipped_twice),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FORMATS;

    /// A row for every format the table says reads height fields, one each.
    #[test]
    fn one_row_per_height_format() {
        for info in FORMATS {
            let rows = CODECS.iter().filter(|c| c.format == info.format).count();
            let want = usize::from(info.height.can_read());
            assert_eq!(rows, want, "{}", info.name);
        }
    }
}
