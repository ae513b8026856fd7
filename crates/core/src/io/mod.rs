//! File output shared by every stage: atomic writes, CSV, NetCDF (CF) and PNG pictures.

pub mod atomic;
pub mod csv;
pub mod geotiff;
pub mod netcdf;
pub mod picture;
pub mod text;

pub use atomic::{write_atomically, AtomicFile};
pub use csv::{csv_of_records, csv_of_rows};

#[cfg(test)]
mod tests {
    /// Stage caches keep outputs as JSON, and a rerun that reloads them must print the same
    /// digits: every f64 reads back bit for bit (serde_json's `float_roundtrip`; without it
    /// about one number in ten in [0, 1) came back one ulp off).
    #[test]
    fn json_numbers_read_back_bit_for_bit() {
        let mut x: u64 = 0x1234_5678_9abc_def1;
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            for v in [(x >> 11) as f64 / (1u64 << 53) as f64, f64::from_bits(x >> 2)] {
                let text = serde_json::to_string(&v).expect("finite");
                let back: f64 = serde_json::from_str(&text).expect("a number");
                assert_eq!(back.to_bits(), v.to_bits(), "{text}");
            }
        }
    }
}
