# The same green as a C# class, called from a script written as for Unity (a MonoBehaviour's FixedUpdate).
# Outside Unity, two stand-ins replace UnityEngine (Vector3, MonoBehaviour) so that Mono compiles the script as is.
bouncelab export --surface green-medium --lang cs --class-name GreenMedium -o GreenMedium.cs
cat > BallOnGreen.cs <<'CS'
using UnityEngine;

// Unity's axes are left-handed with y up; bouncelab's are right-handed with z up. Positions and velocities swap
// y and z; an angular velocity swaps them and changes sign (swapping two axes is a reflection: v = w x r keeps its
// form only if the pseudo-vector w flips).
public class BallOnGreen : MonoBehaviour {
    public Vector3 velocity;         // m/s, as Rigidbody.velocity
    public Vector3 angularVelocity;  // rad/s, as Rigidbody.angularVelocity
    public Vector3 groundNormal = new Vector3(0f, 1f, 0f);
    public Vector3 restPoint;        // where the ball comes to rest (its lowest point), relative to the touch-down
    public float timeToRest;
    public int bounces = -1;

    static double[] ToBouncelab(Vector3 a) { return new double[] { a.x, a.z, a.y }; }
    static double[] SpinToBouncelab(Vector3 w) { return new double[] { -w.x, -w.z, -w.y }; }

    void FixedUpdate() {
        if (bounces >= 0) return;  // the roll-out is known: move the ball along it, or jump to its end
        double[] rest = new double[3];
        double time;
        bounces = GreenMedium.Run(ToBouncelab(velocity), SpinToBouncelab(angularVelocity), ToBouncelab(groundNormal),
                                  rest, out time);
        if (bounces < 0) { Debug.Log("refused: " + GreenMedium.RefusalText(bounces)); return; }
        restPoint = new Vector3((float)rest[0], (float)rest[2], (float)rest[1]);
        timeToRest = (float)time;
    }
}
CS
cat > UnityStandIns.cs <<'CS'
namespace UnityEngine {
    public struct Vector3 {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public override string ToString() { return string.Format("({0:F4}, {1:F4}, {2:F4})", x, y, z); }
    }
    public class MonoBehaviour { }
    public static class Debug { public static void Log(object m) { System.Console.WriteLine(m); } }
}
CS
cat > Main.cs <<'CS'
using System;
using System.Reflection;
using UnityEngine;

public static class Program {  // what Unity does: call FixedUpdate
    public static void Main() {
        // a 9-iron touching down at 18 m/s, 48 degrees, heading +z (forward), 7000 rpm backspin (about -x in Unity)
        BallOnGreen ball = new BallOnGreen();
        ball.velocity = new Vector3(0f, -13.377f, 12.044f);
        ball.angularVelocity = new Vector3(-733.04f, 0f, 0f);
        typeof(BallOnGreen).GetMethod("FixedUpdate", BindingFlags.Instance | BindingFlags.NonPublic).Invoke(ball, null);
        Console.WriteLine("{0} bounces, rest at {1} m (Unity axes) after {2:F4} s", ball.bounces, ball.restPoint,
                          ball.timeToRest);
    }
}
CS
mcs -langversion:ISO-2 -warnaserror+ -out:green.exe Main.cs BallOnGreen.cs UnityStandIns.cs GreenMedium.cs && mono green.exe
echo "# bouncelab.ground, the same landing (the floats as Unity holds them, in bouncelab's axes):"
python - <<'PY'
import numpy as np
from bouncelab.ground import preset, run
f = lambda *x: [float(np.float32(c)) for c in x]
v, w = f(0.0, 12.044, -13.377), f(733.04, 0.0, 0.0)  # (x, z, y) and -(x, z, y) of the Unity vectors
r = run(v, w, preset("green-medium"), units={"velocity": "m/s", "spin": "rad/s"})
x, y, z = (float(np.float32(c)) for c in r.rest_position[0])
print(f"{int(r.totals['bounces'][0])} bounces, rest at ({x:.4f}, {z:.4f}, {y:.4f}) m (Unity axes) after "
      f"{float(np.float32(r.rest_time[0])):.4f} s")
PY
