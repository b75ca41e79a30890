//! # The oracle's column schema, declared once
//!
//! hompm's particle quantities as `check` reads them and as hompm's own
//! state and exact fields are laid out: each quantity's name and its columns
//! in 1D and in 2D (a 2D vector has `_x`, `_y`; a 2D tensor `_xx`, `_yy`,
//! `_xy`, `_yx` for the stress and `_xx`, `_xy`, `_yx`, `_yy` for F, in the
//! order hompm writes them), and whether it is a field of the physics that a
//! verdict needs (u, v, stress, F; issue #35). [`known_columns`],
//! [`field_columns`] and [`x0_columns`] are read off [`QUANTITIES`]; the
//! tables that fill these columns with values (`state`, `check`'s exact
//! fields, `hompm exact`) are tested against it.
//!
//! Items: [`Quantity`], [`QUANTITIES`], [`REPORT_ORDER`], [`known_columns`],
//! [`field_columns`], [`x0_columns`], [`PHYSICAL_FIELDS`], [`quantity`].

use std::sync::OnceLock;

/// One of hompm's particle quantities and its columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Quantity {
    /// Its name in a run's JSON and in a report.
    pub name: &'static str,
    /// Its columns in 1D (empty: not a 1D quantity).
    pub columns_1d: &'static [&'static str],
    /// Its columns in 2D.
    pub columns_2d: &'static [&'static str],
    /// Whether it is a field of the physics (u, v, stress, F): a check
    /// agrees only if it compared one of these for every particle.
    pub physical: bool,
}

impl Quantity {
    /// Its columns in the run's dimension.
    pub fn columns(&self, two_d: bool) -> &'static [&'static str] {
        if two_d {
            self.columns_2d
        } else {
            self.columns_1d
        }
    }
}

/// Every quantity, in the order of [`known_columns`].
pub const QUANTITIES: [Quantity; 9] = [
    Quantity {
        name: "id",
        columns_1d: &["id"],
        columns_2d: &["id"],
        physical: false,
    },
    Quantity {
        name: "x0",
        columns_1d: &["x0"],
        columns_2d: &["x0_x", "x0_y"],
        physical: false,
    },
    Quantity {
        name: "x",
        columns_1d: &["x"],
        columns_2d: &["x_x", "x_y"],
        physical: false,
    },
    Quantity {
        name: "u",
        columns_1d: &["u"],
        columns_2d: &["u_x", "u_y"],
        physical: true,
    },
    Quantity {
        name: "v",
        columns_1d: &["v"],
        columns_2d: &["v_x", "v_y"],
        physical: true,
    },
    Quantity {
        name: "stress",
        columns_1d: &["stress"],
        columns_2d: &["stress_xx", "stress_yy", "stress_xy", "stress_yx"],
        physical: true,
    },
    Quantity {
        name: "F",
        columns_1d: &[],
        columns_2d: &["F_xx", "F_xy", "F_yx", "F_yy"],
        physical: true,
    },
    Quantity {
        name: "volume",
        columns_1d: &["volume"],
        columns_2d: &["volume"],
        physical: false,
    },
    Quantity {
        name: "density",
        columns_1d: &["density"],
        columns_2d: &["density"],
        physical: false,
    },
];

/// The order in which a report lists the compared fields: the physics
/// first, then positions, then volume and density.
pub const REPORT_ORDER: [&str; 8] = ["u", "v", "stress", "F", "x0", "x", "volume", "density"];

/// The fields a verdict needs (issue #35): the names of the physical
/// [`QUANTITIES`].
pub const PHYSICAL_FIELDS: [&str; 4] = ["u", "v", "stress", "F"];

/// The quantity called `name`.
pub fn quantity(name: &str) -> Option<&'static Quantity> {
    QUANTITIES.iter().find(|q| q.name == name)
}

/// hompm's particle columns in 1D or 2D, in [`QUANTITIES`]' order.
pub fn known_columns(two_d: bool) -> &'static [&'static str] {
    static COLUMNS: [OnceLock<Vec<&'static str>>; 2] = [OnceLock::new(), OnceLock::new()];
    COLUMNS[usize::from(two_d)].get_or_init(|| {
        QUANTITIES
            .iter()
            .flat_map(|q| q.columns(two_d).iter().copied())
            .collect()
    })
}

/// The compared fields and their columns, in [`REPORT_ORDER`] (the id is
/// not a field; F only in 2D).
pub fn field_columns(two_d: bool) -> &'static [(&'static str, &'static [&'static str])] {
    type Fields = Vec<(&'static str, &'static [&'static str])>;
    static FIELDS: [OnceLock<Fields>; 2] = [OnceLock::new(), OnceLock::new()];
    FIELDS[usize::from(two_d)].get_or_init(|| {
        REPORT_ORDER
            .iter()
            .filter_map(|name| quantity(name))
            .map(|q| (q.name, q.columns(two_d)))
            .filter(|(_, columns)| !columns.is_empty())
            .collect()
    })
}

/// The initial-position columns of a dimension.
pub fn x0_columns(two_d: bool) -> &'static [&'static str] {
    QUANTITIES[1].columns(two_d)
}
