//! A path's start or goal given in map coordinates, to its grid cell: one conversion, with
//! one set of messages, for `vpmap plan` and the page's `/api/plan`.

use vpmap_plan::{CellXy, Occupancy, OccupancyGrid};

use crate::error::PipelineError;
use crate::ranges::BuildOption;
use crate::text::num;

/// How a point's coordinates read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinates {
    /// The map frame (`+x` right, `+y` up), in `units` (`m`, `camera heights`); the grid's
    /// origin and resolution place the point in a cell.
    Map {
        /// The unit's name in messages.
        units: &'static str,
    },
    /// Whole cell coordinates (column, row; row 0 at the top), as Moving AI maps use.
    Cells,
}

impl Coordinates {
    /// The unit's name in messages (`cells` for [`Coordinates::Cells`]).
    #[must_use]
    pub fn units(self) -> &'static str {
        match self {
            Self::Map { units } => units,
            Self::Cells => "cells",
        }
    }
}

/// Whose option names the messages use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OptionNames {
    /// The command line's flags (`--robot-radius`, `--unknown-passable`).
    CommandLine,
    /// The web API's fields (`robot_radius`, `unknown_passable`).
    WebApi,
}

/// One endpoint of a path request.
#[derive(Debug, Clone, Copy)]
pub struct Endpoint<'a> {
    /// Its name in messages (`start`, `--from`).
    pub name: &'a str,
    /// Where it is, in [`Coordinates`].
    pub point: [f64; 2],
}

/// What a path may enter, and how the messages name the options.
#[derive(Debug, Clone, Copy)]
pub struct EndpointRules {
    /// Unknown cells may be entered.
    pub unknown_passable: bool,
    /// The radius the obstacles were inflated by, in the coordinates' units (only named in
    /// messages).
    pub robot_radius: f64,
    /// Whose option names the messages use.
    pub names: OptionNames,
}

/// The cell of an endpoint, which must be inside the grid and traversable (free, or unknown
/// when [`EndpointRules::unknown_passable`]).
///
/// # Errors
/// [`PipelineError::Endpoint`]: the point is outside the grid, not whole cell coordinates
/// (for [`Coordinates::Cells`]), or on an obstacle or unknown floor; the message names the
/// endpoint, the point, the map's extent or the cell.
pub fn endpoint_cell(
    grid: &OccupancyGrid,
    coordinates: Coordinates,
    endpoint: &Endpoint<'_>,
    rules: &EndpointRules,
) -> Result<CellXy, PipelineError> {
    let name = endpoint.name;
    let [x, y] = endpoint.point;
    let units = coordinates.units();
    let cell = match coordinates {
        Coordinates::Cells => {
            if x.fract() != 0.0 || y.fract() != 0.0 || x < 0.0 || y < 0.0 {
                return Err(PipelineError::Endpoint(format!(
                    "{name} ({}, {}) must be whole cell coordinates (column, row) for a Moving AI map",
                    num(x),
                    num(y)
                )));
            }
            // Compared as numbers first: a huge value saturates when cast to usize.
            if x >= grid.width() as f64 || y >= grid.height() as f64 {
                return Err(PipelineError::Endpoint(format!(
                    "{name} ({}, {}) is outside the {} x {} map",
                    num(x),
                    num(y),
                    grid.width(),
                    grid.height()
                )));
            }
            CellXy::new(x as usize, y as usize)
        }
        Coordinates::Map { .. } => grid.cell_from_world([x, y]).ok_or_else(|| {
            let o = grid.origin_m();
            let r = grid.resolution_m();
            PipelineError::Endpoint(format!(
                "{name} ({}, {}) {units} is outside the map, which spans x {:.2}..{:.2} {units}, y {:.2}..{:.2} {units}",
                num(x),
                num(y),
                o[0],
                o[0] + grid.width() as f64 * r,
                o[1],
                o[1] + grid.height() as f64 * r
            ))
        })?,
    };
    let what_is_there = match grid.get(cell.x, cell.y).unwrap_or(Occupancy::Unknown) {
        Occupancy::Free => return Ok(cell),
        Occupancy::Unknown if rules.unknown_passable => return Ok(cell),
        Occupancy::Occupied if rules.robot_radius > 0.0 => {
            let radius = match rules.names {
                OptionNames::CommandLine => BuildOption::RobotRadius.flag(),
                OptionNames::WebApi => BuildOption::RobotRadius.key(),
            };
            format!(
                "an obstacle (or within {radius} {} {units} of one)",
                num(rules.robot_radius)
            )
        }
        Occupancy::Occupied => "an obstacle".to_owned(),
        // A map from a photo (the page's) has unknown floor; a ROS or Moving AI map has cells.
        Occupancy::Unknown => match rules.names {
            OptionNames::CommandLine => {
                "an unknown cell (use --unknown-passable to allow it)".to_owned()
            }
            OptionNames::WebApi => "unknown floor (outside what the photo shows, or hidden behind an object; set unknown_passable or hidden_free to allow it)".to_owned(),
        },
    };
    Err(PipelineError::Endpoint(format!(
        "{name} ({}, {}) {units} lies on {what_is_there}: cell ({}, {})",
        num(x),
        num(y),
        cell.x,
        cell.y
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> OccupancyGrid {
        // 4 x 2 cells of 0.5 m from (-1, 0): free, occupied, unknown, free on row 0.
        let mut g = OccupancyGrid::new(4, 2, 0.5, [-1.0, 0.0], Occupancy::Free)
            .unwrap_or_else(|e| panic!("{e}"));
        for (x, c) in [(1, Occupancy::Occupied), (2, Occupancy::Unknown)] {
            g.set(x, 0, c).unwrap_or_else(|e| panic!("{e}"));
        }
        g
    }

    fn cell_of(
        p: [f64; 2],
        coordinates: Coordinates,
        rules: EndpointRules,
    ) -> Result<(usize, usize), String> {
        endpoint_cell(
            &grid(),
            coordinates,
            &Endpoint {
                name: "start",
                point: p,
            },
            &rules,
        )
        .map(<(usize, usize)>::from)
        .map_err(|e| e.to_string())
    }

    const METRES: Coordinates = Coordinates::Map { units: "m" };
    const CLI: EndpointRules = EndpointRules {
        unknown_passable: false,
        robot_radius: 0.0,
        names: OptionNames::CommandLine,
    };

    #[test]
    fn points_land_in_their_cells_or_say_why_not() {
        // Row 0 is the top: world y from 0.5 to 1.
        assert_eq!(cell_of([-0.9, 0.9], METRES, CLI), Ok((0, 0)));
        assert_eq!(cell_of([-0.9, 0.1], METRES, CLI), Ok((0, 1)));
        assert_eq!(
            cell_of([5.0, 0.1], METRES, CLI),
            Err(
                "start (5, 0.1) m is outside the map, which spans x -1.00..1.00 m, y 0.00..1.00 m"
                    .to_owned()
            )
        );
        assert_eq!(
            cell_of([-0.4, 0.9], METRES, CLI),
            Err("start (-0.4, 0.9) m lies on an obstacle: cell (1, 0)".to_owned())
        );
        let web = EndpointRules {
            robot_radius: 0.2,
            names: OptionNames::WebApi,
            ..CLI
        };
        assert_eq!(
            cell_of([-0.4, 0.9], METRES, web),
            Err("start (-0.4, 0.9) m lies on an obstacle (or within robot_radius 0.2 m of one): cell (1, 0)".to_owned())
        );
        let unknown = cell_of([0.1, 0.9], METRES, web).err().unwrap_or_default();
        assert!(unknown.contains("lies on unknown floor") && unknown.contains("unknown_passable"));
        let passable = EndpointRules {
            unknown_passable: true,
            ..CLI
        };
        assert_eq!(cell_of([0.1, 0.9], METRES, passable), Ok((2, 0)));
    }

    #[test]
    fn cell_coordinates_must_be_whole_and_inside() {
        assert_eq!(cell_of([3.0, 1.0], Coordinates::Cells, CLI), Ok((3, 1)));
        assert!(
            cell_of([0.5, 1.0], Coordinates::Cells, CLI).is_err_and(|e| e.contains("whole cell"))
        );
        assert_eq!(
            cell_of([4.0, 0.0], Coordinates::Cells, CLI),
            Err("start (4, 0) is outside the 4 x 2 map".to_owned())
        );
        // Far beyond usize: the message shows the number given, not a saturated cast.
        assert_eq!(
            cell_of([1e20, 0.0], Coordinates::Cells, CLI),
            Err("start (1e20, 0) is outside the 4 x 2 map".to_owned())
        );
        assert!(
            cell_of([1.0, 0.0], Coordinates::Cells, CLI)
                .is_err_and(|e| e == "start (1, 0) cells lies on an obstacle: cell (1, 0)")
        );
    }
}
