//! Messages that ask the user to change a fabrication option. The command line calls the
//! option a flag (`--width`), the studio a control on its page ("width"): the library
//! keeps the option itself in the message ([`Advice`]) and each face names it
//! ([`Advice::naming`]), so neither rewrites the other's words.

use crate::limits::OutOfRange;
use std::fmt;

/// A fabrication option a message may ask the user to change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FabOption {
    /// Cut a design that fails verification anyway.
    Force,
    /// The sheet the design is laid out on.
    Media,
    /// The width the design is scaled to.
    Width,
    /// The margin kept clear at the media's edges.
    Margin,
    /// Tile a sheet too large for the media over several pages.
    Tile,
    /// Scale the design to the largest size the media holds.
    Fit,
    /// Print the sheet with registration marks and cut it.
    PrintAndCut,
    /// Score the mountains from the sheet's back.
    MountainsFromBack,
    /// The machine profile.
    Machine,
    /// The glue tab's width on a tube's strip.
    Tab,
}

impl FabOption {
    /// Every option.
    pub const ALL: [FabOption; 10] = [
        FabOption::Force,
        FabOption::Media,
        FabOption::Width,
        FabOption::Margin,
        FabOption::Tile,
        FabOption::Fit,
        FabOption::PrintAndCut,
        FabOption::MountainsFromBack,
        FabOption::Machine,
        FabOption::Tab,
    ];

    /// The option's name in plain words (what the library's own `Display` shows; the
    /// command line's flag is `--` and this).
    pub fn word(self) -> &'static str {
        match self {
            FabOption::Force => "force",
            FabOption::Media => "media",
            FabOption::Width => "width",
            FabOption::Margin => "margin",
            FabOption::Tile => "tile",
            FabOption::Fit => "fit",
            FabOption::PrintAndCut => "print-and-cut",
            FabOption::MountainsFromBack => "mountains-from-back",
            FabOption::Machine => "machine",
            FabOption::Tab => "tab",
        }
    }
}

/// One piece of an [`Advice`].
#[derive(Clone, Debug, PartialEq)]
enum Piece {
    Words(String),
    Option(FabOption),
}

/// A message with the options it asks to change kept as options, for a face to name.
#[derive(Clone, Debug, PartialEq)]
pub struct Advice(Vec<Piece>);

impl Advice {
    /// A message of words only.
    pub fn text(words: impl Into<String>) -> Advice {
        Advice(vec![Piece::Words(words.into())])
    }

    /// The message followed by `words`.
    pub fn then(mut self, words: impl Into<String>) -> Advice {
        self.0.push(Piece::Words(words.into()));
        self
    }

    /// The message followed by an option's name.
    pub fn option(mut self, option: FabOption) -> Advice {
        self.0.push(Piece::Option(option));
        self
    }

    /// An option's value outside its range: the range's message with the option where
    /// it names its input.
    pub fn out_of_range(option: FabOption, error: &OutOfRange) -> Advice {
        Advice(vec![
            Piece::Option(option),
            Piece::Words(error.after_input()),
        ])
    }

    /// The options the message names, in order.
    pub fn options(&self) -> impl Iterator<Item = FabOption> + '_ {
        self.0.iter().filter_map(|p| match p {
            Piece::Option(o) => Some(*o),
            Piece::Words(_) => None,
        })
    }

    /// The message with each option named by `name` (a face's word for it).
    pub fn naming(&self, name: &dyn Fn(FabOption) -> String) -> String {
        self.0
            .iter()
            .map(|p| match p {
                Piece::Words(w) => w.clone(),
                Piece::Option(o) => name(*o),
            })
            .collect()
    }
}

impl fmt::Display for Advice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.naming(&|o| o.word().to_string()))
    }
}

impl From<String> for Advice {
    fn from(words: String) -> Advice {
        Advice::text(words)
    }
}

impl From<&str> for Advice {
    fn from(words: &str) -> Advice {
        Advice::text(words)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_face_names_the_options_its_own_way_and_the_words_stay() {
        let advice = Advice::text("use a larger ")
            .option(FabOption::Media)
            .then(" or ")
            .option(FabOption::Tile);
        let flags = advice.naming(&|o| format!("--{}", o.word()));
        assert_eq!(flags, "use a larger --media or --tile");
        assert_eq!(advice.to_string(), "use a larger media or tile");
        let page = advice.naming(&|o| format!("[{}]", o.word().to_uppercase()));
        assert_eq!(page, "use a larger [MEDIA] or [TILE]");
        assert_eq!(
            advice.options().collect::<Vec<_>>(),
            [FabOption::Media, FabOption::Tile]
        );
    }

    #[test]
    fn a_value_out_of_range_names_its_option_where_the_range_names_its_input() {
        let error = crate::limits::SHEET_WIDTH
            .check("--width", -3.0)
            .unwrap_err();
        let advice = Advice::out_of_range(FabOption::Width, &error);
        assert_eq!(
            advice.naming(&|o| format!("--{}", o.word())),
            error.to_string()
        );
    }

    #[test]
    fn option_words_are_distinct() {
        let words: std::collections::BTreeSet<_> =
            FabOption::ALL.iter().map(|o| o.word()).collect();
        assert_eq!(words.len(), FabOption::ALL.len());
    }
}
