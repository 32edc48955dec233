//! Channels of multi-channel instrument files.
//!
//! A scanning-probe file holds several images of one scan — height, phase,
//! amplitude, current — and a confocal file several layers. A reader with
//! channels lists them ([`ChannelInfo`]) and reads the one a [`Channel`]
//! names; without a choice it reads the height channel SurfaceTopography
//! would (the first channel whose values are lengths). Formats with one
//! channel accept the choice `0` (or their channel's name) and refuse others.

use std::fmt;

use serde::Serialize;

use crate::error::{FResult, FormatError};

/// Which channel to read: its number (from 0) or its name
/// (case-insensitive).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Channel {
    /// The channel's number, from 0.
    Index(usize),
    /// The channel's name, case-insensitive.
    Name(String),
}

impl Channel {
    /// `N` (a number) or a name, as the CLI's `--channel` takes it.
    pub fn parse(text: &str) -> Channel {
        match text.trim().parse() {
            Ok(n) => Channel::Index(n),
            Err(_) => Channel::Name(text.trim().to_string()),
        }
    }
}

impl fmt::Display for Channel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Channel::Index(n) => write!(f, "{n}"),
            Channel::Name(s) => write!(f, "{s:?}"),
        }
    }
}

/// A channel of a file, as `asperity info` lists it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ChannelInfo {
    /// Its number, from 0.
    pub index: usize,
    /// Its name in the file.
    pub name: String,
    /// Whether its values are lengths (a topography).
    pub height: bool,
}

/// The index in `channels` that `choice` names; with no choice the first
/// height channel (else the first).
pub(crate) fn pick(channels: &[ChannelInfo], choice: Option<&Channel>) -> FResult<usize> {
    let found = match choice {
        None => channels
            .iter()
            .position(|c| c.height)
            .or((!channels.is_empty()).then_some(0)),
        Some(Channel::Index(n)) => (*n < channels.len()).then_some(*n),
        Some(Channel::Name(s)) => channels.iter().position(|c| c.name.eq_ignore_ascii_case(s)),
    };
    found.ok_or_else(|| {
        let list: Vec<String> = channels
            .iter()
            .map(|c| format!("{} {:?}", c.index, c.name))
            .collect();
        let what = choice.map_or("a channel".to_string(), |c| format!("channel {c}"));
        FormatError::NoChannel(format!(
            "the file has no {what}; its channels: {}",
            if list.is_empty() {
                "none".into()
            } else {
                list.join(", ")
            }
        ))
    })
}

/// Refuses a choice other than the only channel of a one-channel format.
pub(crate) fn only(choice: Option<&Channel>) -> FResult<()> {
    match choice {
        None | Some(Channel::Index(0)) => Ok(()),
        Some(c) => Err(FormatError::NoChannel(format!(
            "the file holds one channel (0); channel {c} was asked for"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn list() -> Vec<ChannelInfo> {
        ["Phase", "Height", "Height"]
            .iter()
            .enumerate()
            .map(|(index, name)| ChannelInfo {
                index,
                name: name.to_string(),
                height: *name == "Height",
            })
            .collect()
    }

    #[test]
    fn a_channel_is_picked_by_number_by_name_or_as_the_first_height() {
        assert_eq!(pick(&list(), None).unwrap(), 1);
        assert_eq!(pick(&list(), Some(&Channel::parse("2"))).unwrap(), 2);
        assert_eq!(pick(&list(), Some(&Channel::parse("phase"))).unwrap(), 0);
        let e = format!(
            "{:?}",
            pick(&list(), Some(&Channel::parse("Current"))).unwrap_err()
        );
        assert!(
            e.contains("no channel \\\"Current\\\"") && e.contains("0 \\\"Phase\\\""),
            "{e}"
        );
        assert!(pick(&list(), Some(&Channel::Index(3))).is_err());
        assert!(only(Some(&Channel::Index(0))).is_ok() && only(Some(&Channel::Index(1))).is_err());
    }
}
