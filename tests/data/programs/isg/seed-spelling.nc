%L Laengsgewinde
N100 G33 Z48 K1.5                 ;Gewindegang schneiden
N110 G00 X72                      ;Rückzug und Fahren
N120 Z105                         ;auf Startposition
N130 M29                          ;Unterprogrammende

%G33 (Gewindetiefe 0.92 mm)
N10 G51                           ;Anwahl Durchmesserprogrammierung
N15 T1 D1 M03 S400                ;Werkzeuganwahl, Spindel starten
N20 G00 X72 Z105                  ;Anfahren
N25 G01 X69.54 F1000              ;Auf 1. Schnitttiefe positionieren
N30 LL Längsgewinde              ;1. Gewindeschnitt
N35 G01 X69.08                    ;Auf 2. Schnitttiefe positionieren
N30 LL Längsgewinde              ;2. Gewindeschnitt
N35 G01 X68.62                    ;Auf 3. Schnitttiefe positionieren
N30 LL Längsgewinde              ;3. Gewindeschnitt
N35 G01 X68.16                    ;Auf Endtiefe positionieren
N30 LL Längsgewinde              ;4. Gewindeschnitt
N35 G01 X68.16                    ;Erneut auf Endtiefe positionieren
N30 LL Längsgewinde              ;Leerschnitt
N60 M05 X150 Z200                 ;Fahren auf Endposition
N65 M30                           ;Programmende
