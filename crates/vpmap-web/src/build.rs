//! Build script: rebuild the crate whenever a file under `assets/` is added, changed or
//! removed, so that the embedded page is always the folder's current content.

fn main() {
    println!("cargo:rerun-if-changed=assets");
}
