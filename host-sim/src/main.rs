#[allow(dead_code)]
mod reference;

fn main() { println!("host-sim: under construction"); }
