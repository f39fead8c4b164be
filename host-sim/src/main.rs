fn main() {
    println!("host-sim: under construction");
}
