bouncelab fit Rigid no_such_file.csv;                     echo "exit code $?"
printf 'x0,y0,z0,xF,yF,zF\n1,2,3,4,5,6\n' > odd.csv
bouncelab fit Rigid odd.csv;                              echo "exit code $?"
bouncelab fit Foo;                                        echo "exit code $?"
bouncelab fit Rigid A --bounds '{"r": [0, 2]}';           echo "exit code $?"
bouncelab fit Rigid A --bounds '{"r": [0, 2]';            echo "exit code $?"
bouncelab predict Rigid --published C --landing 1 -1 0;   echo "exit code $?"
bouncelab frobnicate 2>&1 | tail -n 1;                    echo "exit code ${PIPESTATUS[0]}"
