# The same law as a C# class, compiled and run with Mono (Unity and Godot compile the same file as it is).
bouncelab fit Rigid A --method structured --save rigid_A.json > /dev/null
bouncelab export rigid_A.json --lang cs --class-name RigidA -o RigidA.cs 2> /dev/null
cat > Main.cs <<'CS'
using System;

public static class Program {
    public static void Main() {
        // two landings: xdot, ydot, omega (radii/s, rad/s), three numbers a landing
        double[] landings = { 1000.0, -800.0, 300.0, 600.0, -900.0, 1500.0 };
        double[] liftoffs = new double[6];
        RigidA.Predict(landings, liftoffs);
        for (int i = 0; i < 6; i += 3) {
            Console.WriteLine("{0} {1} {2} -> {3:G6} {4:G6} {5:G6}", landings[i], landings[i + 1], landings[i + 2],
                              liftoffs[i], liftoffs[i + 1], liftoffs[i + 2]);
        }
        double xdotF, ydotF, omegaF;  // one bounce, allocating nothing
        int code = RigidA.PredictOne(600.0, -900.0, 1500.0, out xdotF, out ydotF, out omegaF);
        Console.WriteLine("regime of the second: {0} ({1})", code, RigidA.RegimeName(code));
    }
}
CS
mcs -out:bounce.exe Main.cs RigidA.cs && mono bounce.exe
