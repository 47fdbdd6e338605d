//! Where a run's rows go: the [`RowSink`] that [`Simulation::run_into`](crate::Simulation::run_into)
//! and [`simulation::run_into`](crate::simulation::run_into) hand each row to as soon as it is
//! computed, and [`History`], the sink that keeps the rows in memory.
//!
//! A run never pre-allocates for all its steps: a sink is told how many rows the run will
//! write if it reaches its end ([`RowSink::header`]) and decides what to do about it —
//! [`History`] refuses a history larger than [`HISTORY_MEMORY_LIMIT`] and reserves at most
//! [`HISTORY_INITIAL_ROWS`] rows up front; a sink that streams to a file (the `flexmbd`
//! program's CSV) keeps nothing.

use crate::Error;

/// What a run writes its rows through: first the columns, then one row per output instant
/// (t, then the sensors, in [`Simulation::sensor_names`](crate::Simulation::sensor_names)
/// order), each as soon as it is computed. An error from the sink ends the run with that
/// error.
pub trait RowSink {
    /// The columns (`t`, then the sensor names), once, before the first step; `rows` is the
    /// number of rows the run writes if it reaches its end (fewer if it fails or is
    /// interrupted).
    fn header(&mut self, columns: &[String], rows: usize) -> Result<(), Error>;

    /// One row: `values[0]` is the time (s), the rest the sensors.
    fn row(&mut self, values: &[f64]) -> Result<(), Error>;
}

/// The most memory (bytes: rows × columns × 8) an in-memory [`History`] may be asked to
/// hold: 4 GiB. A longer run streams its rows through another [`RowSink`].
pub const HISTORY_MEMORY_LIMIT: u128 = 4 << 30;

/// The rows a [`History`] reserves before the first (it grows as rows come).
pub const HISTORY_INITIAL_ROWS: usize = 1024;

/// A recorded history: times and sensor values.
#[derive(Clone, Debug, Default)]
pub struct History {
    /// `t` followed by the sensor names.
    pub header: Vec<String>,
    /// One row per output instant: t, then the sensors.
    pub rows: Vec<Vec<f64>>,
}

impl History {
    /// The column of a sensor.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.header.iter().position(|h| h == name)?;
        Some(self.rows.iter().map(|r| r[k]).collect())
    }
}

impl RowSink for History {
    /// Start afresh with `columns`; refuse ([`Error::HistoryTooLarge`]) a run whose `rows`
    /// would take more than [`HISTORY_MEMORY_LIMIT`].
    fn header(&mut self, columns: &[String], rows: usize) -> Result<(), Error> {
        let bytes = rows as u128 * columns.len() as u128 * 8;
        if bytes > HISTORY_MEMORY_LIMIT {
            return Err(Error::HistoryTooLarge {
                rows,
                columns: columns.len(),
                bytes,
            });
        }
        self.header = columns.to_vec();
        self.rows = Vec::with_capacity(rows.min(HISTORY_INITIAL_ROWS));
        Ok(())
    }

    fn row(&mut self, values: &[f64]) -> Result<(), Error> {
        self.rows.push(values.to_vec());
        Ok(())
    }
}

/// A sink that keeps nothing (a run whose summary is all that is wanted).
#[derive(Clone, Copy, Debug, Default)]
pub struct Discard;

impl RowSink for Discard {
    fn header(&mut self, _columns: &[String], _rows: usize) -> Result<(), Error> {
        Ok(())
    }

    fn row(&mut self, _values: &[f64]) -> Result<(), Error> {
        Ok(())
    }
}
