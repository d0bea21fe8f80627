bouncelab fit Rigid no_such_file.csv;                     echo "exit code $?"
printf 'x0,y0,z0,xF,yF,zF\n1,2,3,4,5,6\n' > odd.csv
bouncelab fit Rigid odd.csv;                              echo "exit code $?"
bouncelab fit Foo;                                        echo "exit code $?"
bouncelab fit Rigid A --bounds '{"r": [0, 2]}';           echo "exit code $?"
bouncelab fit Rigid A --bounds '{"r": [0, 2]';            echo "exit code $?"
bouncelab fit Rigid A --bounds '{"mu": 5}';               echo "exit code $?"
bouncelab fit Rigid A --save no_such_folder/law.json;     echo "exit code $?"
printf 'xdot ydot omega\n1000 -800 200\n900 x 100\n' > landings.txt
bouncelab predict Rigid --published A --input landings.txt; echo "exit code $?"
bouncelab predict Rigid --published C --landing 1 -1 0;   echo "exit code $?"
mkdir notes && echo "mine" > notes/todo.txt
bouncelab reproduce --campaign A --out notes --quiet;     echo "exit code $?"
bouncelab frobnicate 2>&1 | tail -n 1;                    echo "exit code ${PIPESTATUS[0]}"
