//! The Basins view's job (attractors and basins over θν, started while
//! the view is shown and whenever κ, γ, ν, Ω, the solver, its range or
//! its columns change, after the sweep's debounce) and the return map's
//! (the same at the current parameters, with a chaotic set's density,
//! while the return map is shown). Both run through the same backend as
//! every job; a newer one on a lane supersedes the older.

use super::slots::Receive;
use super::{JobKind, Jobs, Slot, SyncOutcome, solver};
use crate::app::settings::{MAX_COLUMNS, MIN_COLUMNS};
use crate::app::settings::{Settings, ViewKind};
use crate::integrate::SolverSettings;
use crate::jobs::{Axis, BasinColumn, BasinsSpec, MapBasinsSpec, Spec};
use crate::model::Params;
use crate::sim::attractors::events::Events;
use crate::sim::attractors::tracks::{Identities, identify};
use crate::sim::attractors::{CellOptions, Found};
use crate::worker::Command;
use crate::worker::Update;

/// The columns of a Basins diagram as they arrive, and the attractors'
/// identities along θν.
#[derive(Clone, Debug, Default)]
pub struct BasinsData {
    /// The parameters but θν (θν = 0) the columns are computed at.
    pub params: Option<Params>,
    /// The θν range.
    pub from: f64,
    pub to: f64,
    /// Each grid column, once it arrived.
    pub columns: Vec<Option<BasinColumn>>,
    /// The attractors' tracks over the columns so far (once every column
    /// is in, as the events joined them).
    pub ids: Identities,
    /// The tracks' births, deaths and period changes, located once every
    /// column is in (never on the page: see `jobs::basins`).
    pub events: Option<Events>,
    /// Bumped whenever a column arrives (the view redraws from it).
    pub revision: u64,
}

impl BasinsData {
    /// An empty diagram of `columns` over [`from`, `to`].
    pub fn new(from: f64, to: f64, columns: usize) -> Self {
        BasinsData {
            from,
            to,
            columns: vec![None; columns],
            ..Self::default()
        }
    }

    /// Takes a column and follows the attractors again.
    pub fn insert(&mut self, c: BasinColumn) {
        if let Some(slot) = self.columns.get_mut(c.index) {
            *slot = Some(c);
        }
        let found: Vec<Option<&Found>> = self
            .columns
            .iter()
            .map(|c| c.as_ref().and_then(|c| c.found.as_ref().ok()))
            .collect();
        self.ids = identify(&found);
        self.revision += 1;
    }

    /// The track of each of `found`'s attractors (found at `params`), as
    /// the diagram's column nearest θν names it: the attractor whose basin
    /// there holds its points. `None` for one the diagram does not show
    /// (other parameters, θν outside its range, no such column).
    pub fn tracks_of(&self, params: &Params, found: &Found) -> Vec<Option<usize>> {
        let none = vec![None; found.attractors.len()];
        let (lo, hi) = (self.from.min(self.to), self.from.max(self.to));
        if self.params != Some(params.with_theta_nu(0.0)) || !(lo..=hi).contains(&params.theta_nu) {
            return none;
        }
        let Some(c) = (0..self.columns.len())
            .filter(|&i| self.columns[i].as_ref().is_some_and(|c| c.found.is_ok()))
            .min_by(|&i, &j| {
                let x = |k: usize| {
                    self.columns[k]
                        .as_ref()
                        .map_or(f64::INFINITY, |c| c.theta_nu)
                };
                (x(i) - params.theta_nu)
                    .abs()
                    .total_cmp(&(x(j) - params.theta_nu).abs())
            })
        else {
            return none;
        };
        let Some(Ok(col)) = self.columns[c].as_ref().map(|c| &c.found) else {
            return none;
        };
        found
            .attractors
            .iter()
            .map(|a| {
                let marks = if a.period.is_some() {
                    &a.points
                } else {
                    &a.iterates
                };
                let mut owners = marks.iter().take(32).map(|&t| col.basin_of(t));
                let first = owners.next()??;
                owners.all(|o| o == Some(first)).then_some(())?;
                self.ids.track(c, first).map(|t| t.id)
            })
            .collect()
    }

    /// Takes the events located once every column is in, and their
    /// tracks (joined where a cycle's continuation showed two as one).
    pub fn take_events(&mut self, events: Events) {
        self.ids = events.ids.clone();
        self.events = Some(events);
        self.revision += 1;
    }

    /// How many columns have arrived.
    pub fn arrived(&self) -> usize {
        self.columns.iter().flatten().count()
    }
}

/// The return map's attractors and basins, for the parameters asked.
#[derive(Clone, Debug, Default)]
pub struct MapBasinsData {
    pub params: Option<Params>,
    pub found: Option<Result<Found, String>>,
}

/// What a Basins diagram is computed for: its parameters but θν, solver,
/// range and columns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasinsKey {
    pub params: Params,
    pub solver: SolverSettings,
    pub range: (f64, f64),
    pub columns: usize,
}

impl BasinsKey {
    /// The Basins view's diagram; while a θν bifurcation diagram marks
    /// births and deaths ([`Settings::diagram_events`]), over that
    /// diagram's range (`sweep_zoom` where it is zoomed) instead.
    pub fn of(s: &Settings, sweep_zoom: Option<(f64, f64)>) -> Self {
        let range = if s.diagram_events() {
            super::continuation::diagram_range(s, sweep_zoom)
        } else {
            s.basins.range(s)
        };
        BasinsKey {
            params: s.params.with_theta_nu(0.0),
            solver: solver(JobKind::Basins, s),
            range,
            columns: s.basins.columns.clamp(MIN_COLUMNS, MAX_COLUMNS),
        }
    }
}

/// What the Basins jobs were last started with, and when a change was
/// first seen (the debounce).
#[derive(Clone, Debug, Default)]
pub struct BasinsSent {
    diagram: Option<BasinsKey>,
    changed_at: Option<f64>,
    map: Option<(Params, SolverSettings)>,
    map_changed_at: Option<f64>,
}

/// Whether a change of what `kind` depends on, first seen at `*at`, has
/// waited its debounce by `now` (then it is forgotten); if not, `out` is
/// told when to look again.
fn settled(kind: JobKind, at: &mut Option<f64>, now: f64, out: &mut SyncOutcome) -> bool {
    let since = now - *at.get_or_insert(now);
    let debounce = kind.debounce();
    if since >= debounce {
        *at = None;
        true
    } else {
        out.wait(debounce - since);
        false
    }
}

impl Jobs {
    /// Starts the Basins diagram for `key`.
    pub fn restart_basins(&mut self, s: &Settings, key: BasinsKey) {
        let g = self.generation();
        let revision = self.basins.data.revision + 1;
        let mut data = BasinsData::new(key.range.0, key.range.1, key.columns);
        data.revision = revision;
        data.params = Some(key.params);
        self.basins.start(g, data);
        self.bind(JobKind::Basins, s, (0.0, 0.0));
        let spec = BasinsSpec {
            params: key.params,
            settings: key.solver,
            param: crate::sim::continuation::ContParam::ThetaNu,
            axis: Axis::new(key.range.0, key.range.1, key.columns),
            cells: CellOptions::column(),
        };
        self.send(Command::Run {
            generation: g,
            spec: Spec::Basins(spec),
        });
        self.basins_sent.diagram = Some(key);
    }

    /// Starts the return map's basins at `params`.
    pub(super) fn restart_map_basins(&mut self, s: &Settings, settings: SolverSettings) {
        let params = s.params;
        let g = self.generation();
        let data = MapBasinsData {
            params: Some(params),
            found: None,
        };
        self.map_basins.start(g, data);
        self.bind(JobKind::MapBasins, s, (0.0, 0.0));
        self.send(Command::Run {
            generation: g,
            spec: Spec::MapBasins(MapBasinsSpec::here(params, settings)),
        });
        self.basins_sent.map = Some((params, settings));
    }

    /// Starts what the shown Basins view (or a diagram's births and
    /// deaths) and the return map now call for,
    /// once a change has been still for the sweep's debounce (at once the
    /// first time, or for a zoom or a new column count).
    pub(super) fn sync_basins(
        &mut self,
        s: &Settings,
        shown: &super::Shown,
        out: &mut SyncOutcome,
    ) {
        let now = shown.now;
        if s.shows(ViewKind::Basins) || s.diagram_events() {
            let key = BasinsKey::of(s, shown.sweep_zoom);
            match self.basins_sent.diagram {
                None => self.restart_basins(s, key),
                Some(sent) if sent != key => {
                    let view_only = sent.params == key.params && sent.solver == key.solver;
                    if view_only
                        || settled(JobKind::Basins, &mut self.basins_sent.changed_at, now, out)
                    {
                        self.restart_basins(s, key);
                    }
                }
                _ => {}
            }
        }
        if s.shows(ViewKind::ReturnMap) {
            let want = (s.params, solver(JobKind::MapBasins, s));
            match self.basins_sent.map {
                None => self.restart_map_basins(s, want.1),
                Some(sent)
                    if sent != want
                        && settled(
                            JobKind::MapBasins,
                            &mut self.basins_sent.map_changed_at,
                            now,
                            out,
                        ) =>
                {
                    self.restart_map_basins(s, want.1);
                }
                _ => {}
            }
        }
    }
}

impl Slot<MapBasinsData> {
    /// The attractors at `params`, once found.
    pub fn at(&self, params: &Params) -> Option<&Found> {
        if self.data.params.as_ref() != Some(params) {
            return None;
        }
        self.data.found.as_ref()?.as_ref().ok()
    }
}

impl Receive for BasinsData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Basins { column, .. } => self.insert(*column),
            Update::BasinEvents { events, .. } => self.take_events(*events),
            u => return Some(u),
        }
        None
    }
}

impl Receive for MapBasinsData {
    fn receive(&mut self, u: Update) -> Option<Update> {
        match u {
            Update::Basins { column, .. } => {
                self.found = Some(column.found);
                None
            }
            u => Some(u),
        }
    }
}
